/* Decals integrated over the renderer's pixel filter (docs/pixel-filter.md): taps on the
 * pixel's tangent plane at the filter's quadrature offsets, each integrating its stratum. */
#ifndef DECALCOMP_PIXEL_FILTER_H
#define DECALCOMP_PIXEL_FILTER_H

#include "clean_depth.h"
#include "frame_reads.h"
#include "matrix.h"
#include "reconstruct.h"
#include "shared_types.h"

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

/* How a pixel is integrated: point-sampled at its centre, over its tangent plane, or split
 * between two surfaces' planes at a silhouette. */
#define DC_TAPS_POINT 0
#define DC_TAPS_PLANE 1
#define DC_TAPS_SPLIT 2

typedef struct {
    int mode;
    DcTapRays rays;
    DcTapPlane plane;
    /* DC_TAPS_SPLIT: `plane` is the nearer surface, `other` the farther; a tap at pixel offset
     * (u, v) lies on `plane` for its share dc_tap_share (a ramp across the line
     * dot(split_dir, (u, v)) = split_c, one stratum wide) and on `other` for the rest. */
    DcTapPlane other;
    float2 split_dir;
    float split_c, split_width;
    /* each surface's own material, for `plane` [0] and `other` [1]: its clean pixel's as the file
     * holds it, (albedo, roughness) and metallic, then as the decals so far left it (the mean over
     * the surface's taps); decals blend into these, not into the mix */
    float4 material[2];
    float metallic[2];
    float3 normal[2]; /* each surface's camera-space normal, as decals turn it */
} DcTaps;

/* The share of the tap at pixel offset (u, v) that lies on the split's nearer surface. */
inline float dc_tap_share(const DcTaps* t, float u, float v) {
    return clamp((t->split_c - (t->split_dir.x * u + t->split_dir.y * v)) / t->split_width + 0.5f, 0.0f, 1.0f);
}

/* The rays of pixel (x, y)'s footprint (dc_pixel_ray at its centre and one pixel right and down):
 * one unprojection, the neighbours' by the inverse projection's steps per pixel. */
DC_CPU_INLINE void dc_pixel_rays(__constant const DcFrame* f, int x, int y, DcTapRays* r) {
    const __constant float* m = f->inv_projection;
    const float2 ndc = dc_pixel_ndc(f, x, y);
    const float4 c = dc_mul4_constant(m, (float4)(ndc, 0.0f, 1.0f));
    const float su = 2.0f / (float)f->display_width, sv = -2.0f / (float)f->display_height;
    const float4 cu = c + (float4)(m[0], m[4], m[8], m[12]) * su, cv = c + (float4)(m[1], m[5], m[9], m[13]) * sv;
    r->dir = c.xyz / c.w;
    r->dir_u = cu.xyz / cu.w - r->dir;
    r->dir_v = cv.xyz / cv.w - r->dir;
    r->origin = r->origin_u = r->origin_v = (float3)(0.0f);
    if (f->orthographic) { /* the origins on the near plane (NDC z = -1), moving with the pixel */
        const float4 near = (float4)(m[2], m[6], m[10], m[14]);
        const float4 o = c - near, ou = cu - near, ov = cv - near;
        r->origin = o.xyz / o.w;
        r->origin_u = ou.xyz / ou.w - r->origin;
        r->origin_v = ov.xyz / ov.w - r->origin;
        r->dir -= r->origin;
        r->dir_u -= r->origin_u;
        r->dir_v -= r->origin_v;
    }
}

/* The tap at pixel offset (u, v) on `plane`; false when its ray misses it in front of the camera. */
inline bool dc_tap_point(const DcTapRays* r, const DcTapPlane* plane, float u, float v, float3* out) {
    const float3 o = r->origin + r->origin_u * u + r->origin_v * v;
    const float3 d = r->dir + r->dir_u * u + r->dir_v * v;
    const float denom = dot(d, plane->n);
    if (!(denom * denom > 1e-12f * dot(d, d))) return false;
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
DC_CPU_INLINE bool dc_tap_plane(__constant const DcFrame* f, const DcTapRays* rays, float3 point, float3 n,
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
    /* The footprint's corners: the ray at offset (u, v) meets the plane at
     * t = (k - g(u, v)) / e(u, v), g and e affine in (u, v), so only their view depth is computed.
     * Behind the camera (t <= 0), parallel (e = 0: an infinite depth) or more than
     * DC_FILTER_GRAZING away in depth: grazing. The four corners are a vector's lanes (a CPU's
     * work-item then divides once for all four). */
    const float r = f->filter_radius;
    const float k = dot(c, n);
    const float g0 = dot(rays->origin, n), gu = dot(rays->origin_u, n), gv = dot(rays->origin_v, n);
    const float e0 = dot(rays->dir, n), eu = dot(rays->dir_u, n), ev = dot(rays->dir_v, n);
    const float4 u = (float4)(-r, r, -r, r), v = (float4)(-r, -r, r, r);
    const float4 t = (k - (g0 + gu * u + gv * v)) / (e0 + eu * u + ev * v);
    const float4 z = rays->origin.z + rays->origin_u.z * u + rays->origin_v.z * v +
                     (rays->dir.z + rays->dir_u.z * u + rays->dir_v.z * v) * t;
    if (!all(t > 0.0f) || !all(fabs(z - c.z) <= DC_FILTER_GRAZING * fabs(c.z))) return false;
    /* Within DC_FILTER_GRAZING of the centre's depth, the projective map strays less than 25 %
     * from its linear part (docs/pixel-filter.md "Integrated evaluation"): this bounds every tap. */
    const float step = 0.5f * f->filter_step, du = length(plane->du), dv = length(plane->dv);
    plane->reach = (1.25f * r + step) * (du + dv);
    return true;
}

/* Silhouettes (docs/pixel-filter.md "Silhouettes"): a pixel with a 4-neighbour more than
 * DC_MIXED_DEPTH_JUMP away in view depth may average a nearer and a farther surface (its depth is
 * one sample's: renderers do not filter depth). Its taps go to the planes of the nearest clean
 * pixel of each surface within the window, split by a line across the direction from the nearer
 * surface's clean pixels to the farther's. The line sits where the nearer surface's share of the
 * filter matches the share that its albedo and normal have in the pixel's filtered ones. Clean
 * pixels: clean_depth.h. */
/* the window reaches at most this many pixels from the pixel (binning adds one tile around each) */
#define DC_SPLIT_WINDOW 3
/* how far the share's mix of the surfaces' normals may miss the pixel's normal */
#define DC_SPLIT_NORMAL_FIT 0.5f
/* bisection steps placing the split line: 2^-16 of the footprint */
#define DC_SPLIT_STEPS 16

/* The filter's weight on the nearer surface with the split line at c. */
inline float dc_split_weight(__constant const DcFrame* f, DcTaps* t, float c) {
    t->split_c = c;
    float sum = 0.0f;
    for (int j = 0; j < f->filter_taps; ++j)
        for (int i = 0; i < f->filter_taps; ++i)
            sum += f->filter_weight[i] * f->filter_weight[j] * dc_tap_share(t, f->filter_offset[i], f->filter_offset[j]);
    return sum;
}

/* The nearer surface's share of a mixed pixel: v = w near + (1 - w) far for its filtered albedo,
 * least squares over the channels. Where the albedos are too alike to tell (DC_SHARE_CONTRAST), the
 * normal pass instead: less exact, since a curved surface's normal at the silhouette differs from
 * its clean pixel's. -1 where neither tells the surfaces apart. */
#define DC_SHARE_CONTRAST 0.01f
inline float dc_mixed_share(float3 albedo, float3 albedo_near, float3 albedo_far, float3 normal, float3 normal_near,
                            float3 normal_far, int has_normal) {
    const float3 da = albedo_near - albedo_far, dn = normal_near - normal_far;
    float w = -1.0f;
    if (dot(da, da) > DC_SHARE_CONTRAST) w = dot(albedo - albedo_far, da) / dot(da, da);
    else if (has_normal && dot(dn, dn) > DC_SHARE_CONTRAST) w = dot(normal - normal_far, dn) / dot(dn, dn);
    else return -1.0f;
    return isfinite(w) ? clamp(w, 0.0f, 1.0f) : -1.0f; /* a NaN or infinite pass: no split */
}

/* A clean pixel's camera-space normal: its normal pass, else from its depths. */
inline float3 dc_clean_normal(__constant const DcFrame* f, __global const float* depth_plane,
                              __global const float4* position_plane, __global const float4* original1,
                              int has_normal, int x, int y, float3 q) {
    if (has_normal) return normalize(dc_world_to_camera_vector(f, original1[(size_t)y * f->width + x].xyz));
    return dc_normal_from_depth(f, depth_plane, position_plane, x, y, q);
}

/* Splits a silhouette pixel's taps between its two surfaces (see above). `original0/1`: the
 * material planes as the file holds them (the albedo group; the normal group where `has_normal`),
 * since neighbours' planes may already hold their decals; `clean_depths`: dc_clean_depths' plane.
 * Leaves t as it is where the pixel is not a silhouette or its surfaces cannot be told apart. */
inline void dc_split_silhouette(__constant const DcFrame* f, __global const float* depth_plane,
                                __global const float4* position_plane, __global const float4* original0,
                                __global const float4* original1, __global const float* clean_depths,
                                int has_normal, int x, int y, float3 p, float depth_step, DcTaps* t) {
    const float z = -p.z;
    /* depth_step: the largest view-depth step to a 4-neighbour (dc_taps has point-sampled pixels
     * beside background: every 4-neighbour here has a point) */
    if (!(depth_step > DC_MIXED_DEPTH_JUMP * z)) return;
    /* pass 0: the depth range of the window's clean pixels; pass 1: the nearer and the farther
     * half, each one's nearest pixel and the mean offset */
    const int window = clamp((int)ceil(f->filter_radius + 0.5f) + 1, 2, DC_SPLIT_WINDOW);
    float z_min = MAXFLOAT, z_max = 0.0f;
    int2 near_px = (int2)(0), far_px = (int2)(0);
    int near_d2 = 1 << 20, far_d2 = 1 << 20;
    float2 near_sum = (float2)(0.0f), far_sum = (float2)(0.0f);
    float near_count = 0.0f, far_count = 0.0f;
    for (int pass = 0; pass < 2; ++pass) {
        const float z_mid = 0.5f * (z_min + z_max);
        for (int dy = -window; dy <= window; ++dy)
            for (int dx = -window; dx <= window; ++dx) {
                const int nx = x + dx, ny = y + dy;
                float zq;
                if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= f->width || ny >= f->height ||
                    !dc_clean_at(f, clean_depths, depth_plane, position_plane, nx, ny, &zq))
                    continue;
                if (pass == 0) {
                    z_min = fmin(z_min, zq);
                    z_max = fmax(z_max, zq);
                    continue;
                }
                const int d2 = dx * dx + dy * dy;
                if (zq < z_mid) {
                    near_sum += (float2)(dx, dy);
                    near_count += 1.0f;
                    if (d2 < near_d2) { near_d2 = d2; near_px = (int2)(nx, ny); }
                } else {
                    far_sum += (float2)(dx, dy);
                    far_count += 1.0f;
                    if (d2 < far_d2) { far_d2 = d2; far_px = (int2)(nx, ny); }
                }
            }
        if (!(z_max - z_min > DC_MIXED_DEPTH_JUMP * z)) return;
    }
    float2 dir = far_sum / far_count - near_sum / near_count;
    if (!(length(dir) > 0.25f)) return;
    dir = normalize(dir);
    float3 pn, pf;
    if (!dc_reconstruct(f, depth_plane, position_plane, near_px.x, near_px.y, &pn) ||
        !dc_reconstruct(f, depth_plane, position_plane, far_px.x, far_px.y, &pf))
        return;
    const size_t i = (size_t)y * f->width + x, in = (size_t)near_px.y * f->width + near_px.x,
                 jf = (size_t)far_px.y * f->width + far_px.x;
    const float share = dc_mixed_share(original0[i].xyz, original0[in].xyz, original0[jf].xyz,
                                       has_normal ? original1[i].xyz : (float3)(0.0f),
                                       has_normal ? original1[in].xyz : (float3)(0.0f),
                                       has_normal ? original1[jf].xyz : (float3)(0.0f), has_normal);
    if (share < 0.0f) return;
    /* the two surfaces' normals mixed by the share must come near the pixel's: a third surface that
     * the pixel mostly shows (a face seen edge-on between the two) is not explained by them */
    if (has_normal && !(length(share * normalize(original1[in].xyz) + (1.0f - share) * normalize(original1[jf].xyz) -
                               original1[i].xyz) <= DC_SPLIT_NORMAL_FIT))
        return;
    DcTaps s = *t;
    if (!dc_tap_plane(f, &s.rays, pn, dc_clean_normal(f, depth_plane, position_plane, original1, has_normal,
                                                      near_px.x, near_px.y, pn), &s.plane) ||
        !dc_tap_plane(f, &s.rays, pf, dc_clean_normal(f, depth_plane, position_plane, original1, has_normal,
                                                      far_px.x, far_px.y, pf), &s.other))
        return;
    /* the line where the filter's weight on the nearer side is the nearer surface's share */
    s.split_dir = dir;
    s.split_width = f->filter_step * (fabs(dir.x) + fabs(dir.y));
    const float reach = f->filter_radius + s.split_width;
    const float total = dc_split_weight(f, &s, reach);
    float lo = -reach, hi = reach;
    for (int it = 0; it < DC_SPLIT_STEPS; ++it) {
        const float c = 0.5f * (lo + hi);
        if (dc_split_weight(f, &s, c) < share * total) lo = c; else hi = c;
    }
    s.split_c = 0.5f * (lo + hi);
    s.material[0] = original0[in];
    s.material[1] = original0[jf];
    const bool has_group1 = dc_has_group1(f);
    s.metallic[0] = has_group1 ? original1[in].w : 0.0f;
    s.metallic[1] = has_group1 ? original1[jf].w : 0.0f;
    s.normal[0] = s.plane.n;
    s.normal[1] = s.other.n;
    s.mode = DC_TAPS_SPLIT;
    *t = s;
}

/* Creases (docs/pixel-filter.md "Creases"): a pixel whose normal pass is shorter than
 * DC_MIXED_NORMAL_LENGTH without a depth jump averages two faces meeting at an edge. Its taps go to
 * the planes of the faces' nearest clean pixels (continuous depth and a unit normal), split along
 * the edge itself: the image of the line where the two planes meet. */
#define DC_CLEAN_NORMAL_LENGTH 0.999f
/* the faces' normals turn by more than about 11 degrees */
#define DC_CREASE_FACE_COS 0.98f
/* and each face's clean normals agree within about 2.6 degrees: curved surfaces are not creases */
#define DC_CREASE_FLAT_COS 0.999f
/* how far the split's mix of the faces' normals may miss the pixel's normal */
#define DC_CREASE_NORMAL_FIT 0.15f

/* Whether a normal pass is shorter than a clean one (and not zero): a pixel averaging faces. */
inline bool dc_mixed_normal(float3 normal_pass) {
    const float len = length(normal_pass);
    return len < DC_MIXED_NORMAL_LENGTH && len > 0.0f;
}

/* The two faces around pixel (x, y) whose mixed normal pass is `mix`: their world normals and
 * nearest clean pixels. Pass 0 takes the clean normal turned furthest from the mix, pass 1 the one
 * turned furthest from that, pass 2 gives each clean pixel to the nearer of the two. False where
 * the window holds no such two flat faces. */
inline bool dc_crease_faces(__constant const DcFrame* f, __global const float* depth_plane,
                            __global const float4* position_plane, __global const float4* original1,
                            __global const float* clean_depths, int x, int y, float3 mix, float3 face[2],
                            int2 px[2]) {
    const int window = clamp((int)ceil(f->filter_radius + 0.5f) + 1, 2, DC_SPLIT_WINDOW);
    int best_d2[2] = {1 << 20, 1 << 20};
    for (int pass = 0; pass < 3; ++pass) {
        const float3 from = pass == 0 ? normalize(mix) : face[0];
        float3 pick = from;
        float least = 2.0f;
        for (int dy = -window; dy <= window; ++dy)
            for (int dx = -window; dx <= window; ++dx) {
                const int nx = x + dx, ny = y + dy;
                float zq;
                if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= f->width || ny >= f->height) continue;
                const float3 n = original1[(size_t)ny * f->width + nx].xyz;
                if (!(fabs(length(n) - 1.0f) <= 1.0f - DC_CLEAN_NORMAL_LENGTH) ||
                    !dc_clean_at(f, clean_depths, depth_plane, position_plane, nx, ny, &zq))
                    continue;
                if (pass < 2) {
                    const float c = dot(n, from);
                    if (c < least) { least = c; pick = n; }
                    continue;
                }
                const int side = dot(n, face[1]) > dot(n, face[0]) ? 1 : 0;
                if (!(dot(n, face[side]) >= DC_CREASE_FLAT_COS * length(n))) return false;
                const int d2 = dx * dx + dy * dy;
                if (d2 < best_d2[side]) { best_d2[side] = d2; px[side] = (int2)(nx, ny); }
            }
        if (pass == 2) break;
        if (!(least < 2.0f)) return false;
        face[pass] = normalize(pick);
    }
    return dot(face[0], face[1]) < DC_CREASE_FACE_COS && best_d2[0] < (1 << 20) && best_d2[1] < (1 << 20);
}

/* Zero on the image of the line where planes a and b meet; its sign tells which plane the ray at
 * pixel offset (u, v) meets first (dc_split_crease). Exactly linear in (u, v) for perspective and
 * orthographic rays. */
inline float dc_crease_side(const DcTapRays* r, const DcTapPlane* a, const DcTapPlane* b, float u, float v) {
    const float3 o = r->origin + r->origin_u * u + r->origin_v * v;
    const float3 d = r->dir + r->dir_u * u + r->dir_v * v;
    return dot(o - a->p, a->n) * dot(d, b->n) - dot(o - b->p, b->n) * dot(d, a->n);
}

/* Splits a crease pixel's taps between its two faces (see above); leaves t as it is elsewhere.
 * `mix`: the pixel's own normal pass (original1's at the pixel, as the kernel already loaded it). */
inline void dc_split_crease(__constant const DcFrame* f, __global const float* depth_plane,
                            __global const float4* position_plane, __global const float4* original0,
                            __global const float4* original1, __global const float* clean_depths, int x, int y,
                            float3 p, float3 mix, DcTaps* t) {
    const size_t i = (size_t)y * f->width + x;
    if (!dc_mixed_normal(mix)) return;
    float3 face[2];
    int2 px[2];
    if (!dc_crease_faces(f, depth_plane, position_plane, original1, clean_depths, x, y, mix, face, px)) return;
    float3 pa, pb;
    if (!dc_reconstruct(f, depth_plane, position_plane, px[0].x, px[0].y, &pa) ||
        !dc_reconstruct(f, depth_plane, position_plane, px[1].x, px[1].y, &pb))
        return;
    DcTaps s = *t;
    if (!dc_tap_plane(f, &s.rays, pa, normalize(dc_world_to_camera_vector(f, face[0])), &s.plane) ||
        !dc_tap_plane(f, &s.rays, pb, normalize(dc_world_to_camera_vector(f, face[1])), &s.other))
        return;
    /* both faces pass through the pixel's own point, as one surface does (no depth jump) */
    if (!(fabs(s.plane.p.z - p.z) <= DC_MIXED_DEPTH_JUMP * fabs(p.z)) ||
        !(fabs(s.other.p.z - p.z) <= DC_MIXED_DEPTH_JUMP * fabs(p.z)))
        return;
    /* the edge's image through the footprint: dc_crease_side linearised at the centre */
    const float f00 = dc_crease_side(&s.rays, &s.plane, &s.other, 0.0f, 0.0f);
    const float2 g = (float2)(dc_crease_side(&s.rays, &s.plane, &s.other, 1.0f, 0.0f) - f00,
                              dc_crease_side(&s.rays, &s.plane, &s.other, 0.0f, 1.0f) - f00);
    const float len = length(g);
    if (!(len > 0.0f) || !isfinite(len)) return;
    float c = -f00 / len;
    float2 dir = g / len;
    if (!(fabs(c) <= f->filter_radius)) return; /* the edge misses the footprint */
    /* dc_crease_side < 0 (face 0's side of the line) where face 0 is the farther plane, when both
     * face the camera. A ray sees the farther plane across a convex edge and the nearer across a
     * concave one (face 1's clean point above face 0's plane): flip the line where face 0 is hidden. */
    const bool concave = dot(pb - pa, s.plane.n) > 0.0f;
    const bool facing = dot(s.rays.dir, s.plane.n) * dot(s.rays.dir, s.other.n) > 0.0f;
    if (concave == facing) {
        dir = -dir;
        c = -c;
    }
    s.split_dir = dir;
    s.split_width = f->filter_step * (fabs(dir.x) + fabs(dir.y));
    /* Each face's clean material, both shifted by one offset so that their mix under the filter's
     * weight on each side is the pixel's own: faces of one material both take the pixel's, and a
     * textured face keeps the texture under the footprint rather than its neighbour's texel. */
    const float near_weight = dc_split_weight(f, &s, c) / dc_split_weight(f, &s, MAXFLOAT);
    /* the faces' normals mixed by the split's weights must give the pixel's: an occluding edge that
     * merely passes near where the planes would meet fails here */
    if (!(length(near_weight * face[0] + (1.0f - near_weight) * face[1] - mix) <= DC_CREASE_NORMAL_FIT)) return;
    const size_t ia = (size_t)px[0].y * f->width + px[0].x, ib = (size_t)px[1].y * f->width + px[1].x;
    const float4 shift = original0[i] - (near_weight * original0[ia] + (1.0f - near_weight) * original0[ib]);
    const float metallic_shift =
        original1[i].w - (near_weight * original1[ia].w + (1.0f - near_weight) * original1[ib].w);
    s.split_c = c; /* (dc_split_weight moved it) */
    s.material[0] = original0[ia] + shift;
    s.material[1] = original0[ib] + shift;
    s.metallic[0] = original1[ia].w + metallic_shift;
    s.metallic[1] = original1[ib].w + metallic_shift;
    s.normal[0] = s.plane.n;
    s.normal[1] = s.other.n;
    s.mode = DC_TAPS_SPLIT;
    *t = s;
}

/* How pixel (x, y) at p with camera-space unit normal n is integrated (docs/pixel-filter.md
 * "Mixed pixels"): over its own tangent plane, also at silhouettes and creases (whose averaged
 * depth and normal make a plane between the surfaces), but point-sampled beside background and
 * at grazing angles. `normal_pass`: the pixel's world normal as the file holds it (original1's at
 * the pixel, which the caller has loaded already). */
DC_CPU_INLINE DcTaps dc_taps(__constant const DcFrame* f, __global const float* depth_plane,
                             __global const float4* position_plane, __global const float4* original0,
                             __global const float4* original1, __global const float* clean_depths, int has_normal,
                             int x, int y, float3 p, float3 n, float3 normal_pass) {
    DcTaps t;
    t.mode = DC_TAPS_POINT;
    /* the 4-neighbours' largest view-depth step (planar depth reads them without unprojecting):
     * beside background (MAXFLOAT) the pixel is point-sampled; the step tells silhouettes */
    const float depth_step = dc_depth_step(f, depth_plane, position_plane, x, y, -p.z);
    if (depth_step == MAXFLOAT) return t;
    dc_pixel_rays(f, x, y, &t.rays);
    if (dc_tap_plane(f, &t.rays, p, n, &t.plane)) t.mode = DC_TAPS_PLANE;
    /* (each split's own first test here too: most pixels then skip a call, on CPUs a costly one) */
    if (depth_step > DC_MIXED_DEPTH_JUMP * -p.z)
        dc_split_silhouette(f, depth_plane, position_plane, original0, original1, clean_depths, has_normal, x, y, p,
                            depth_step, &t);
    if (has_normal && t.mode == DC_TAPS_PLANE && dc_mixed_normal(normal_pass))
        dc_split_crease(f, depth_plane, position_plane, original0, original1, clean_depths, x, y, p, normal_pass, &t);
    return t;
}

/* Whether decal d may reach a footprint of camera-space radius `radius` around the local point l:
 * the footprint's bounding sphere against its volume. */
inline bool dc_filter_may_reach_at(__global const DcDecal* d, float3 l, float radius) {
    const float3 reach = vload3(0, d->local_scale) * radius;
    if (d->kind == DC_KIND_BOX || d->kind == DC_KIND_VOLUME)
        return fabs(l.x) - reach.x <= 0.5f && fabs(l.y) - reach.y <= 0.5f && fabs(l.z) - reach.z <= 0.5f;
    const float r = fmax(reach.x, fmax(reach.y, reach.z));
    if (d->kind == DC_KIND_CUBE) return length(l) - r <= 0.5f;
    const float dist = -l.z;
    const float half_h = (dist + r) * d->tan_half_fov_y;
    return dist + r >= d->near_plane && dist - r <= d->far_plane && fabs(l.x) - r <= half_h * d->aspect &&
           fabs(l.y) - r <= half_h;
}

/* Whether decal d may reach any tap on the plane. */
inline bool dc_filter_may_reach(__global const DcDecal* d, const DcTapPlane* tp) {
    return dc_filter_may_reach_at(d, dc_affine_global(d->camera_to_local, tp->p), tp->reach);
}

/* A decal's local vector for a camera-space one (camera_to_local's linear part). */
inline float3 dc_camera_to_local_vector(__global const DcDecal* d, float3 v) {
    return (float3)(dot(vload3(0, d->camera_to_local), v), dot(vload3(0, d->camera_to_local + 4), v),
                    dot(vload3(0, d->camera_to_local + 8), v));
}

#endif
