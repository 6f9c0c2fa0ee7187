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
