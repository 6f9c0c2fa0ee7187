/* Texture-space decals (docs/texture-space.md): each pixel of a bound object reaches its rest-pose
 * point through the UV pass (rest_pose.cl), and its decals are evaluated there, in the rest mesh's
 * object space, as world decals are in camera space. A per-pixel rotation (rest -> camera, from the
 * mesh's tangent frame and the neighbours' rest and camera points) carries normals across. */
#ifndef DECALCOMP_REST_POSE_H
#define DECALCOMP_REST_POSE_H

#include "decal_kinds.h"
#include "materials.h"
#include "pixel_filter.h"
#include "shared_types.h"

/* Unit quaternion (x, y, z, w) rotations. */
inline float3 dc_quat_rotate(float4 q, float3 v) {
    const float3 t = 2.0f * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}
inline float3 dc_quat_rotate_inverse(float4 q, float3 v) { return dc_quat_rotate((float4)(-q.xyz, q.w), v); }

/* The difference towards the neighbour on one axis (dx, dy) that is on the object (w > 0) and nearer:
 * in a plane of UVs (bake mode) a neighbour across a UV seam names a far-away UV, in a plane of
 * rest points one across a fold or silhouette a far-away point. False when neither is on it. */
inline bool dc_neighbour_step(__global const float4* plane, int width, int height, int x, int y, int dx, int dy,
                              float4 centre, float4* step) {
    float best = MAXFLOAT;
    for (int side = 1; side >= -1; side -= 2) {
        const int nx = x + side * dx, ny = y + side * dy;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const float4 r = plane[(size_t)ny * width + nx];
        if (!(r.w > 0.0f)) continue;
        const float4 d = (r - centre) * (float)side;
        if (length(d.xyz) < best) { /* w is a flag or a triangle number, not a coordinate */
            best = length(d.xyz);
            *step = d;
        }
    }
    return best < MAXFLOAT;
}

/* A bake-mode decal (d->rest_baked) at pixel (x, y): its UV-space layers read at the pixel's UV
 * (s = u, t = 1 - v: the layer's row 0 is v = 1), bilinear, or through their mip chain with the
 * footprint of the UV differences to the same-object neighbours. The bake holds the fades. */
DC_INLINE DcSurface dc_apply_baked_decal(__constant const DcFrame* frame, __global const DcDecal* d,
                                         __global const float4* uvs, int x, int y, float3 normal, float weight,
                                         __global const DcTexture* textures, __global const float4* texels,
                                         DcSurface s, const int variant, int* applied) {
    const float4 r = uvs[(size_t)y * frame->width + x];
    if (!(r.w > 0.0f)) return s; /* not the object, or no usable UV */
    DcLookup lk;
    lk.fade = 1.0f;
    lk.face = 0;
    lk.filtered = 0;
    lk.integrated = 0;
    lk.facing = (float3)(0.0f);
    lk.coord = lk.coord_dx = lk.coord_dy = (float3)(r.x, 1.0f - r.y, 0.0f);
    lk.has_footprint = 0;
    float4 step_x, step_y;
    if (d->filter == DC_FILTER_MIP &&
        dc_neighbour_step(uvs, frame->width, frame->height, x, y, 1, 0, r, &step_x) &&
        dc_neighbour_step(uvs, frame->width, frame->height, x, y, 0, 1, r, &step_y)) {
        lk.coord_dx = (float3)(r.x + step_x.x, 1.0f - r.y - step_x.y, 0.0f);
        lk.coord_dy = (float3)(r.x + step_y.x, 1.0f - r.y - step_y.y, 0.0f);
        lk.has_footprint = 1;
    }
    /* the albedo layer's alpha is the coverage: pixels it misses stay untouched (and unwritten) */
    if (!(dc_lookup_texel(d, lk, textures, texels, d->texture, variant).w > 0.0f)) return s;
    *applied = 1;
    return dc_apply_decal(frame, d, lk, textures, texels, weight, normal, s, variant);
}

/* Blends decal d, looked up in rest space, into s: the surface's normal goes to rest space (q: the
 * pixel's rest -> camera rotation), the decal is applied there and a turned normal comes back. */
DC_INLINE DcSurface dc_blend_in_rest_space(__constant const DcFrame* frame, __global const DcDecal* d, DcLookup lk,
                                           float4 q, float3 rest_normal, float weight,
                                           __global const DcTexture* textures, __global const float4* texels,
                                           DcSurface s, const int variant) {
    DcSurface rest = s;
    rest.normal = dc_quat_rotate_inverse(q, s.normal);
    rest.normal_changed = 0;
    rest = dc_apply_decal(frame, d, lk, textures, texels, weight, rest_normal, rest, variant);
    rest.normal = rest.normal_changed ? dc_quat_rotate(q, rest.normal) : s.normal;
    rest.normal_changed |= s.normal_changed;
    return rest;
}

/* Decal d integrated over the pixel filter at a texture-space pixel (docs/pixel-filter.md): the
 * taps' rest points follow the surface through the neighbours' rest points, P + u dP/dx + v dP/dy
 * at the filter's pixel offsets (u, v), each tap prefiltering its stratum and blending as a point
 * sample does; the pixel takes their weighted mean. `step_x`, `step_y`: dP per pixel. */
DC_INLINE DcSurface dc_filter_rest_decal(__constant const DcFrame* frame, __global const DcDecal* d, float3 p,
                                         float3 step_x, float3 step_y, float4 q, float3 rest_normal, int has_normal,
                                         float weight, __global const DcTexture* textures,
                                         __global const float4* texels, DcSurface s, const int variant,
                                         int* applied) {
    DcTapPlane footprint; /* only its centre and reach are used, in rest space */
    footprint.p = p;
    footprint.reach = (frame->filter_radius + 0.5f * frame->filter_step) * (length(step_x) + length(step_y));
    if (!dc_filter_may_reach(d, &footprint)) return s;
    const float3 su = dc_camera_to_local_vector(d, step_x) * frame->filter_step;
    const float3 sv = dc_camera_to_local_vector(d, step_y) * frame->filter_step;
    DcSurface acc = dc_surface_add_scaled(s, s, -1.0f);
    int touched = 0;
    for (int j = 0; j < frame->filter_taps; ++j)
        for (int i = 0; i < frame->filter_taps; ++i) {
            const float3 pt = p + step_x * frame->filter_offset[i] + step_y * frame->filter_offset[j];
            DcSurface out = s;
            const DcLookup lk = dc_decal_lookup_at(d, pt, rest_normal, has_normal, pt, pt, 1, 1, su, sv);
            if (lk.fade > 0.0f) {
                out = dc_blend_in_rest_space(frame, d, lk, q, rest_normal, weight, textures, texels, s, variant);
                touched = 1;
            }
            acc = dc_surface_add_scaled(acc, out, frame->filter_weight[i] * frame->filter_weight[j]);
        }
    if (!touched) return s;
    if (acc.normal_changed && length(acc.normal) > 1e-6f) acc.normal = normalize(acc.normal);
    *applied = 1;
    return acc;
}

/* Decal d (d->rest_binding >= 0) at pixel (x, y): the point is the pixel's rest point, directions
 * are taken to rest space and back, the mip footprint comes from the neighbours' rest points.
 * `normal` is the pixel's camera-space normal. With `filtered` (the frame has a pixel filter and the
 * pixel is integrated, pixel_filter.h) the decal is integrated over the filter when both neighbour
 * steps exist, else point-sampled. Sets *applied when the decal reached the pixel. */
DC_INLINE DcSurface dc_apply_rest_decal(__constant const DcFrame* frame, __global const DcDecal* d,
                                        __global const float4* rest_points, __global const float4* rest_frames,
                                        int x, int y, float3 normal, int has_normal, int filtered, float weight,
                                        __global const DcTexture* textures, __global const float4* texels,
                                        DcSurface s, const int variant, int* applied) {
    const size_t pixels = (size_t)frame->width * frame->height;
    const size_t plane = (size_t)d->rest_binding * pixels;
    __global const float4* points = rest_points + plane;
    const size_t i = (size_t)y * frame->width + x;
    if (d->rest_baked)
        return dc_apply_baked_decal(frame, d, points, x, y, normal, weight, textures, texels, s, variant, applied);
    const float4 r = points[i];
    if (!(r.w > 0.0f)) return s; /* not the object, or no triangle holds the pixel's UV */
    const float3 p = r.xyz;
    const float4 q = frame->rest_frames ? rest_frames[plane + i] : (float4)(0, 0, 0, 1);
    const float3 rest_normal = dc_quat_rotate_inverse(q, normal);
    const int rest_has_normal = has_normal && frame->rest_frames;
    float4 step_x, step_y;
    if (filtered && dc_neighbour_step(points, frame->width, frame->height, x, y, 1, 0, r, &step_x) &&
        dc_neighbour_step(points, frame->width, frame->height, x, y, 0, 1, r, &step_y))
        return dc_filter_rest_decal(frame, d, p, step_x.xyz, step_y.xyz, q, rest_normal, rest_has_normal, weight,
                                    textures, texels, s, variant, applied);
    float3 p_dx = p, p_dy = p;
    int footprint = 0;
    if (d->filter == DC_FILTER_MIP) {
        /* one pixel right and down, from the nearer neighbour on each axis that is on the mesh */
        const int xn = x + 1 < frame->width ? x + 1 : x - 1, yn = y + 1 < frame->height ? y + 1 : y - 1;
        const float4 rx = xn >= 0 ? points[(size_t)y * frame->width + xn] : (float4)(0.0f);
        const float4 ry = yn >= 0 ? points[(size_t)yn * frame->width + x] : (float4)(0.0f);
        if (rx.w > 0.0f && ry.w > 0.0f) {
            p_dx = xn > x ? rx.xyz : 2.0f * p - rx.xyz;
            p_dy = yn > y ? ry.xyz : 2.0f * p - ry.xyz;
            footprint = 1;
        }
    }
    const DcLookup lk = dc_decal_lookup(d, p, rest_normal, rest_has_normal, p_dx, p_dy, footprint);
    if (!(lk.fade > 0.0f)) return s;
    *applied = 1;
    return dc_blend_in_rest_space(frame, d, lk, q, rest_normal, weight, textures, texels, s, variant);
}

#endif
