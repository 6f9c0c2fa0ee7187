/* Blast occlusion maps (docs/conventions.md "Blast occlusion"): per occluding decal, the least
 * distance from the decal's origin seen in each map texel, stored as the bits of a positive
 * float in a uint (positive floats order like their bits, so atomic_min works on them).
 * A frustum map spans the frustum's own (s, t); a cube map has six faces (OpenGL rule). */
#ifndef DECALCOMP_OCCLUSION_H
#define DECALCOMP_OCCLUSION_H

#include "shared_types.h"
#include "decal_kinds.h"
#include "texture_sample.h"

/* Slopes are clamped to this tangent: steeper surfaces get this bias (grazing beyond ~86 deg). */
#define DC_OCCLUSION_MAX_SLOPE 16.0f

/* A map texel: face (0 for a frustum) and column i, row j (row 0 at t = 0). */
typedef struct {
    int face, i, j;
} DcMapTexel;

/* The texel a decal-local point falls in. False when the point has no texel: behind the
 * projector or outside its cone (frustum), or at the centre (cube). */
inline bool dc_occlusion_texel(__global const DcDecal* d, float3 l, DcMapTexel* out) {
    const int w = d->occlusion_width, h = d->occlusion_height;
    float2 st;
    if (d->kind == DC_KIND_CUBE) {
        if (!(length(l) > 0.0f)) return false;
        out->face = dc_cube_face(l);
        st = dc_cube_face_st(l, out->face);
    } else {
        if (!(-l.z > 0.0f)) return false;
        out->face = 0;
        st = dc_frustum_st(d, l);
        if (!(st.x >= 0.0f && st.x <= 1.0f && st.y >= 0.0f && st.y <= 1.0f)) return false;
    }
    out->i = clamp((int)floor(st.x * (float)w), 0, w - 1);
    out->j = clamp((int)floor(st.y * (float)h), 0, h - 1);
    return true;
}

inline int dc_occlusion_index(__global const DcDecal* d, DcMapTexel t) {
    return d->occlusion_map + (t.face * d->occlusion_height + t.j) * d->occlusion_width + t.i;
}

/* The texel (di, dj) steps from t. A frustum map ends at its edges (false); on a cube the step
 * past a face's edge continues on the neighbouring face through the texel centre's direction. */
inline bool dc_occlusion_step(__global const DcDecal* d, DcMapTexel t, int di, int dj, DcMapTexel* out) {
    const int w = d->occlusion_width, h = d->occlusion_height;
    *out = t;
    out->i += di;
    out->j += dj;
    if (out->i >= 0 && out->j >= 0 && out->i < w && out->j < h) return true;
    if (d->kind != DC_KIND_CUBE) return false;
    const float3 dir =
        dc_cube_face_dir(t.face, 2.0f * ((float)out->i + 0.5f) / (float)w - 1.0f, 2.0f * ((float)out->j + 0.5f) / (float)h - 1.0f);
    out->face = dc_cube_face(dir);
    const float2 st = dc_cube_face_st(dir, out->face);
    out->i = clamp((int)floor(st.x * (float)w), 0, w - 1);
    out->j = clamp((int)floor(st.y * (float)h), 0, h - 1);
    return true;
}

/* Size of one texel in tangent units (lateral extent per unit of distance), the largest over the
 * map: 2 tan(fov/2) aspect / width or 2 tan(fov/2) / height (frustum), 2 / resolution (cube). */
inline float dc_occlusion_texel_tangent(__global const DcDecal* d) {
    if (d->kind == DC_KIND_CUBE) return 2.0f / (float)d->occlusion_width;
    return fmax(2.0f * d->tan_half_fov_y * d->aspect / (float)d->occlusion_width,
                2.0f * d->tan_half_fov_y / (float)d->occlusion_height);
}

/* Whether the blast reaches camera-space point p (surface normal n, camera space): its distance
 * from the origin is at most the least distance stored in its texel and the 8 around it, plus
 * bias = occlusion_bias * distance * texel_tangent * clamp(tan(slope), 1, DC_OCCLUSION_MAX_SLOPE),
 * the slope being the angle between the surface normal and the direction to the origin, both in
 * decal-local space. */
inline bool dc_blast_reaches(__global const DcDecal* d, __global const uint* maps, float3 p, float3 n) {
    const float3 l = dc_affine_global(d->camera_to_local, p);
    DcMapTexel centre;
    if (!dc_occlusion_texel(d, l, &centre)) return true; /* outside the map: nothing recorded */
    const float dist = length(l);
    uint nearest = maps[dc_occlusion_index(d, centre)];
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
            DcMapTexel t;
            if ((di != 0 || dj != 0) && dc_occlusion_step(d, centre, di, dj, &t))
                nearest = min(nearest, maps[dc_occlusion_index(d, t)]);
        }
    /* the normal in local space: (M^-1)^-T n, i.e. the local_to_camera rows combined by n */
    const float3 n_local = n.x * vload3(0, d->local_to_camera) + n.y * vload3(0, d->local_to_camera + 4) +
                           n.z * vload3(0, d->local_to_camera + 8);
    const float c = fabs(dot(normalize(n_local), l)) / dist;
    const float slope = c > 0.0f ? sqrt(fmax(1.0f - c * c, 0.0f)) / c : DC_OCCLUSION_MAX_SLOPE;
    const float bias =
        d->occlusion_bias * dist * dc_occlusion_texel_tangent(d) * clamp(slope, 1.0f, DC_OCCLUSION_MAX_SLOPE);
    return dist <= as_float(nearest) + bias;
}

#endif
