/* Texture-space decals (docs/texture-space.md): each pixel of a bound object reaches its rest-pose
 * point through the UV pass (rest_pose.cl), and its decals are evaluated there, in the rest mesh's
 * object space, as world decals are in camera space. A per-pixel rotation (rest -> camera, from the
 * mesh's tangent frame and the neighbours' rest and camera points) carries normals across. */
#ifndef DECALCOMP_REST_POSE_H
#define DECALCOMP_REST_POSE_H

#include "decal_kinds.h"
#include "materials.h"
#include "shared_types.h"

/* Unit quaternion (x, y, z, w) rotations. */
inline float3 dc_quat_rotate(float4 q, float3 v) {
    const float3 t = 2.0f * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}
inline float3 dc_quat_rotate_inverse(float4 q, float3 v) { return dc_quat_rotate((float4)(-q.xyz, q.w), v); }

/* The UV difference towards the same-object neighbour on one axis whose UV is nearer (a neighbour
 * across a UV seam names a far-away UV); false when neither is on the object. */
inline bool dc_uv_step(__global const float4* uvs, int width, int height, int x, int y, int dx, int dy, float2 uv,
                       float2* step) {
    float best = MAXFLOAT;
    for (int side = 1; side >= -1; side -= 2) {
        const int nx = x + side * dx, ny = y + side * dy;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const float4 r = uvs[(size_t)ny * width + nx];
        if (!(r.w > 0.0f)) continue;
        const float2 d = (r.xy - uv) * (float)side;
        if (length(d) < best) {
            best = length(d);
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
    lk.facing = (float3)(0.0f);
    lk.coord = lk.coord_dx = lk.coord_dy = (float3)(r.x, 1.0f - r.y, 0.0f);
    lk.has_footprint = 0;
    float2 step_x, step_y;
    if (d->filter == DC_FILTER_MIP &&
        dc_uv_step(uvs, frame->width, frame->height, x, y, 1, 0, r.xy, &step_x) &&
        dc_uv_step(uvs, frame->width, frame->height, x, y, 0, 1, r.xy, &step_y)) {
        lk.coord_dx = (float3)(r.x + step_x.x, 1.0f - r.y - step_x.y, 0.0f);
        lk.coord_dy = (float3)(r.x + step_y.x, 1.0f - r.y - step_y.y, 0.0f);
        lk.has_footprint = 1;
    }
    /* the albedo layer's alpha is the coverage: pixels it misses stay untouched (and unwritten) */
    if (!(dc_lookup_texel(d, lk, textures, texels, d->texture, variant).w > 0.0f)) return s;
    *applied = 1;
    return dc_apply_decal(frame, d, lk, textures, texels, weight, normal, s, variant);
}

/* Decal d (d->rest_binding >= 0) at pixel (x, y): the point is the pixel's rest point, directions
 * are taken to rest space and back, the mip footprint comes from the neighbours' rest points.
 * `normal` is the pixel's camera-space normal. Sets *applied when the decal reached the pixel. */
DC_INLINE DcSurface dc_apply_rest_decal(__constant const DcFrame* frame, __global const DcDecal* d,
                                        __global const float4* rest_points, __global const float4* rest_frames,
                                        int x, int y, float3 normal, int has_normal, float weight,
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
    const float4 q = frame->rest_frames ? rest_frames[plane + i] : (float4)(0, 0, 0, 1);
    const float3 rest_normal = dc_quat_rotate_inverse(q, normal);
    const DcLookup lk = dc_decal_lookup(d, p, rest_normal, has_normal && frame->rest_frames, p_dx, p_dy, footprint);
    if (!(lk.fade > 0.0f)) return s;
    DcSurface rest = s;
    rest.normal = dc_quat_rotate_inverse(q, s.normal);
    rest.normal_changed = 0;
    rest = dc_apply_decal(frame, d, lk, textures, texels, weight, rest_normal, rest, variant);
    rest.normal = rest.normal_changed ? dc_quat_rotate(q, rest.normal) : s.normal;
    rest.normal_changed |= s.normal_changed;
    *applied = 1;
    return rest;
}

#endif
