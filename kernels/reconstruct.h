/* Camera-space position of a G-buffer pixel from its depth or position pass
 * (docs/conventions.md: pixel centres, depth conventions, background). */
#ifndef DECALCOMP_RECONSTRUCT_H
#define DECALCOMP_RECONSTRUCT_H

#include "shared_types.h"
#include "matrix.h"

/* NDC of data-window position (px, py), in pixels from the window's top-left corner; row 0 is the
 * top row. */
inline float2 dc_ndc_at(__constant const DcFrame* f, float px, float py) {
    return (float2)(2.0f * (px + (float)f->origin_x) / (float)f->display_width - 1.0f,
                    1.0f - 2.0f * (py + (float)f->origin_y) / (float)f->display_height);
}

/* NDC of the centre of data-window pixel (x, y). */
inline float2 dc_pixel_ndc(__constant const DcFrame* f, int x, int y) {
    return dc_ndc_at(f, (float)x + 0.5f, (float)y + 0.5f);
}

inline float3 dc_unproject(__constant const DcFrame* f, float2 ndc, float ndc_z) {
    const float4 c = dc_mul4_constant(f->inv_projection, (float4)(ndc, ndc_z, 1.0f));
    return c.xyz / c.w;
}

/* The camera-space point at view depth z (-z in camera space) on the ray through `ndc`. */
inline float3 dc_point_at_view_depth(__constant const DcFrame* f, float2 ndc, float z) {
    if (f->orthographic) {
        const float3 a = dc_unproject(f, ndc, -1.0f);
        return (float3)(a.x, a.y, -z);
    }
    const float3 q = dc_unproject(f, ndc, 0.0f); /* on the ray, in front: finite with an infinite far plane */
    return q * (z / -q.z);
}

/* A world-space direction in camera space (the linear part of world_to_camera). */
inline float3 dc_world_to_camera_vector(__constant const DcFrame* f, float3 v) {
    return (float3)(dot(vload3(0, f->world_to_camera), v), dot(vload3(0, f->world_to_camera + 4), v),
                    dot(vload3(0, f->world_to_camera + 8), v));
}

/* Relative view-depth step between 4-neighbours beyond which a filtered frame's pixel mixes two
 * surfaces (a silhouette): the beauty's mixed pixels and the pixel filter's split taps. */
#define DC_MIXED_DEPTH_JUMP 0.02f
/* A normal pass shorter than this: the filter averaged differing normals. */
#define DC_MIXED_NORMAL_LENGTH 0.995f

inline bool dc_is_background_depth(float d) { return !(d > 0.0f) || isinf(d) || d >= DC_BACKGROUND_DEPTH; }

/* Pixel (x, y)'s depth sample (1 where the frame has no depth pass). */
inline float dc_pixel_depth(__constant const DcFrame* f, __global const float* depth_plane, int x, int y) {
    return f->has_depth ? depth_plane[(size_t)y * f->width + x] : 1.0f;
}

/* Writes the camera-space point of pixel (x, y), whose depth sample is d (dc_pixel_depth), and
 * returns true, or returns false for background (invalid depth, beyond the far plane, or too close
 * to the camera). */
inline bool dc_reconstruct_from(__constant const DcFrame* f, float d, __global const float4* position_plane, int x,
                                int y, float3* p_out) {
    const size_t i = (size_t)y * f->width + x;
    const float2 ndc = dc_pixel_ndc(f, x, y);
    float3 p;

    if (f->depth_convention == DC_DEPTH_POSITION) {
        if (f->has_depth && dc_is_background_depth(d)) return false;
        const float3 w = position_plane[i].xyz;
        if (any(isnan(w)) || any(isinf(w))) return false;
        p = dc_affine_constant(f->world_to_camera, w);
    } else if (f->depth_convention == DC_DEPTH_NDC) {
        if (isnan(d) || (f->reversed_z ? d <= 0.0f : d >= 1.0f) || d < 0.0f || d > 1.0f) return false;
        const float ndc_z = f->reversed_z ? 1.0f - 2.0f * d : 2.0f * d - 1.0f;
        p = dc_unproject(f, ndc, ndc_z);
    } else {
        if (dc_is_background_depth(d)) return false;
        p = f->depth_convention == DC_DEPTH_RADIAL && !f->orthographic ? normalize(dc_unproject(f, ndc, 0.0f)) * d
                                                                         : dc_point_at_view_depth(f, ndc, d);
    }
    if (!f->orthographic && !(-p.z >= DC_MIN_VIEW_DEPTH)) return false;
    if (f->far_plane > 0.0f && -p.z > f->far_plane) return false;
    if (any(isnan(p)) || any(isinf(p))) return false;
    *p_out = p;
    return true;
}

/* dc_reconstruct_from with the pixel's depth read here. */
inline bool dc_reconstruct(__constant const DcFrame* f, __global const float* depth_plane,
                           __global const float4* position_plane, int x, int y, float3* p_out) {
    return dc_reconstruct_from(f, dc_pixel_depth(f, depth_plane, x, y), position_plane, x, y, p_out);
}

/* The view depth (-z) of pixel (x, y) for the tile ranges, false for background. Planar depth
 * is the view depth itself, so it needs no unprojection; its validity test is widened by a few
 * ulps so that no pixel dc_reconstruct keeps is dropped (tile ranges only need to be conservative,
 * and binning adds its own slack). Other conventions reconstruct the point. */
inline bool dc_view_depth(__constant const DcFrame* f, __global const float* depth_plane,
                          __global const float4* position_plane, int x, int y, float* z_out) {
    if (f->depth_convention == DC_DEPTH_PLANAR && f->has_depth) {
        const float d = depth_plane[(size_t)y * f->width + x];
        if (dc_is_background_depth(d)) return false;
        if (!f->orthographic && !(d >= DC_MIN_VIEW_DEPTH * (1.0f - 1e-5f))) return false;
        if (f->far_plane > 0.0f && d > f->far_plane * (1.0f + 1e-5f)) return false;
        *z_out = d;
        return true;
    }
    float3 p;
    if (!dc_reconstruct(f, depth_plane, position_plane, x, y, &p)) return false;
    *z_out = -p.z;
    return true;
}

/* The ray through the centre of pixel (x, y): origin + t dir, t > 0 in front of the camera. */
inline void dc_pixel_ray(__constant const DcFrame* f, int x, int y, float3* origin, float3* dir) {
    const float2 ndc = dc_pixel_ndc(f, x, y);
    const float3 far_point = dc_unproject(f, ndc, 0.0f); /* finite with an infinite far plane */
    *origin = f->orthographic ? dc_unproject(f, ndc, -1.0f) : (float3)(0.0f);
    *dir = far_point - *origin;
}

/* Footprint of pixel (x, y): where the rays of its right and lower neighbours meet the plane
 * through p with normal n (no neighbour depth is read, so silhouettes cannot disturb it).
 * Returns 0 when a ray runs parallel to the plane or meets it behind the camera. */
inline int dc_footprint(__constant const DcFrame* f, int x, int y, float3 p, float3 n, float3* p_dx, float3* p_dy) {
    for (int a = 0; a < 2; ++a) {
        float3 origin, dir;
        dc_pixel_ray(f, x + (a == 0), y + (a == 1), &origin, &dir);
        const float denom = dot(dir, n);
        if (!(fabs(denom) > 1e-6f * length(dir))) return 0;
        const float t = dot(p - origin, n) / denom;
        if (!(t > 0.0f)) return 0;
        if (a == 0) *p_dx = origin + dir * t;
        else *p_dy = origin + dir * t;
    }
    return 1;
}

/* Camera-space normal of pixel (x, y) from its neighbours' points (seed 004): per axis, the
 * neighbour whose depth is closer to this pixel's, so differences never straddle a silhouette.
 * Falls back to facing the camera where no neighbour is valid. */
inline float3 dc_normal_from_depth(__constant const DcFrame* f, __global const float* depth_plane,
                                   __global const float4* position_plane, int x, int y, float3 p) {
    float3 axis[2];
    int found = 0;
    for (int a = 0; a < 2; ++a) {
        float3 best = (float3)(0.0f);
        float best_gap = MAXFLOAT;
        for (int side = -1; side <= 1; side += 2) {
            const int nx = a == 0 ? x + side : x, ny = a == 0 ? y : y + side;
            float3 q;
            if (nx < 0 || ny < 0 || nx >= f->width || ny >= f->height ||
                !dc_reconstruct(f, depth_plane, position_plane, nx, ny, &q))
                continue;
            const float gap = fabs(q.z - p.z);
            if (gap < best_gap) {
                best_gap = gap;
                best = (q - p) * (float)side; /* always towards +x / +y */
            }
        }
        if (best_gap < MAXFLOAT) {
            axis[a] = best;
            ++found;
        }
    }
    const float3 towards_camera = -normalize(p);
    if (found < 2) return towards_camera;
    float3 n = cross(axis[0], axis[1]);
    if (!(length(n) > 0.0f)) return towards_camera;
    n = normalize(n);
    return dot(n, towards_camera) < 0.0f ? -n : n;
}

#endif
