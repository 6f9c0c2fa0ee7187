/* Decals integrated over the renderer's pixel filter (docs/pixel-filter.md): taps on the
 * pixel's tangent plane at the filter's quadrature offsets, each integrating its stratum. */
#ifndef DECALCOMP_PIXEL_FILTER_H
#define DECALCOMP_PIXEL_FILTER_H

#include "shared_types.h"
#include "matrix.h"
#include "reconstruct.h"

/* The rays of a pixel's footprint: origin(u, v) + t dir(u, v), affine in the pixel offset (u, v)
 * from its centre (exact for projective cameras). */
typedef struct {
    float3 origin, origin_u, origin_v, dir, dir_u, dir_v;
} DcTapRays;

/* A plane the taps land on: through p with camera-space unit normal n. */
typedef struct {
    float3 p, n;
    float3 du, dv;  /* tangent-plane step per pixel at the centre */
    float reach;    /* camera-space radius holding every tap and half a stratum around it */
} DcTapPlane;

/* How a pixel is integrated: point-sampled at its centre, or over its tangent plane. */
#define DC_TAPS_POINT 0
#define DC_TAPS_PLANE 1

typedef struct {
    int mode;
    DcTapRays rays;
    DcTapPlane plane;
} DcTaps;

/* The tap at pixel offset (u, v) on `plane`; false when its ray misses it in front of the camera. */
inline bool dc_tap_point(const DcTapRays* r, const DcTapPlane* plane, float u, float v, float3* out) {
    const float3 o = r->origin + r->origin_u * u + r->origin_v * v;
    const float3 d = r->dir + r->dir_u * u + r->dir_v * v;
    const float denom = dot(d, plane->n);
    if (!(fabs(denom) > 1e-6f * length(d))) return false;
    const float t = dot(plane->p - o, plane->n) / denom;
    if (!(t > 0.0f)) return false;
    *out = o + d * t;
    return true;
}

/* Relative depth a footprint corner may stray from its plane's depth at the pixel centre: beyond
 * it the footprint leaves the surface (grazing views) and the pixel is point-sampled. The binning
 * widens decal depth ranges by DC_FILTER_DEPTH_SLACK so that no reachable decal is missed. */
#define DC_FILTER_GRAZING 0.04f
#define DC_FILTER_DEPTH_SLACK 0.05f

/* Sets up a plane through `point` with unit normal n for the rays; false at grazing angles. */
inline bool dc_tap_plane(__constant const DcFrame* f, const DcTapRays* rays, float3 point, float3 n,
                         DcTapPlane* plane) {
    plane->p = point;
    plane->n = n;
    float3 c, a, b;
    if (!dc_tap_point(rays, plane, 0.0f, 0.0f, &c) || !dc_tap_point(rays, plane, 1.0f, 0.0f, &a) ||
        !dc_tap_point(rays, plane, 0.0f, 1.0f, &b))
        return false;
    plane->p = c; /* the plane's point on the pixel's own ray */
    plane->du = a - c;
    plane->dv = b - c;
    /* the footprint's corners bound every tap (the plane's map from pixel offsets is projective) */
    const float r = f->filter_radius;
    float reach = 0.0f;
    for (int k = 0; k < 4; ++k) {
        float3 corner;
        if (!dc_tap_point(rays, plane, (k & 1) ? r : -r, (k & 2) ? r : -r, &corner)) return false;
        if (!(fabs(corner.z - c.z) <= DC_FILTER_GRAZING * fabs(c.z))) return false;
        reach = fmax(reach, length(corner - c));
    }
    plane->reach = reach + 0.5f * f->filter_step * (length(plane->du) + length(plane->dv));
    return true;
}

/* How pixel (x, y) at p with camera-space unit normal n is integrated (docs/pixel-filter.md
 * "Mixed pixels"): over its own tangent plane, also at silhouettes and creases (whose averaged
 * depth and normal make a plane between the surfaces), but point-sampled beside background and
 * at grazing angles. */
inline DcTaps dc_taps(__constant const DcFrame* f, __global const float* depth_plane,
                      __global const float4* position_plane, int x, int y, float3 p, float3 n) {
    DcTaps t;
    t.mode = DC_TAPS_POINT;
    for (int k = 0; k < 4; ++k) {
        const int nx = x + (k == 0) - (k == 1), ny = y + (k == 2) - (k == 3);
        float3 q;
        if (nx >= 0 && ny >= 0 && nx < f->width && ny < f->height &&
            !dc_reconstruct(f, depth_plane, position_plane, nx, ny, &q))
            return t;
    }
    float3 o1, d1, o2, d2;
    dc_pixel_ray(f, x, y, &t.rays.origin, &t.rays.dir);
    dc_pixel_ray(f, x + 1, y, &o1, &d1);
    dc_pixel_ray(f, x, y + 1, &o2, &d2);
    t.rays.origin_u = o1 - t.rays.origin;
    t.rays.origin_v = o2 - t.rays.origin;
    t.rays.dir_u = d1 - t.rays.dir;
    t.rays.dir_v = d2 - t.rays.dir;
    if (dc_tap_plane(f, &t.rays, p, n, &t.plane)) t.mode = DC_TAPS_PLANE;
    return t;
}

/* Whether decal d may reach any tap on the plane: the footprint's bounding sphere against its volume. */
inline bool dc_filter_may_reach(__global const DcDecal* d, const DcTapPlane* tp) {
    const float3 l = dc_affine_global(d->camera_to_local, tp->p);
    const float3 reach = vload3(0, d->local_scale) * tp->reach;
    if (d->kind == DC_KIND_BOX || d->kind == DC_KIND_VOLUME)
        return fabs(l.x) - reach.x <= 0.5f && fabs(l.y) - reach.y <= 0.5f && fabs(l.z) - reach.z <= 0.5f;
    const float r = fmax(reach.x, fmax(reach.y, reach.z));
    if (d->kind == DC_KIND_CUBE) return length(l) - r <= 0.5f;
    const float dist = -l.z;
    const float half_h = (dist + r) * d->tan_half_fov_y;
    return dist + r >= d->near_plane && dist - r <= d->far_plane && fabs(l.x) - r <= half_h * d->aspect &&
           fabs(l.y) - r <= half_h;
}

/* A decal's local vector for a camera-space one (camera_to_local's linear part). */
inline float3 dc_camera_to_local_vector(__global const DcDecal* d, float3 v) {
    return (float3)(dot(vload3(0, d->camera_to_local), v), dot(vload3(0, d->camera_to_local + 4), v),
                    dot(vload3(0, d->camera_to_local + 8), v));
}

#endif
