/* Per-kind projection of a camera-space point into a decal (docs/conventions.md "Decals"):
 * the inside test, the kind's own falloff and fades, and where its textures are looked up. */
#ifndef DECALCOMP_DECAL_KINDS_H
#define DECALCOMP_DECAL_KINDS_H

#include "shared_types.h"
#include "matrix.h"
#include "texture_sample.h"

inline float dc_ramp_down(float x, float full, float none) { return clamp((none - x) / (none - full), 0.0f, 1.0f); }

/* Angle fade against a unit direction the receiving surface should face. Back faces get 0. */
inline float dc_angle_fade(__global const DcDecal* d, float3 normal, float3 facing) {
    const float c = dot(normal, facing);
    if (!(c > 0.0f)) return 0.0f;
    /* atan2 of sine and cosine stays accurate near 0 degrees, where acos loses half its digits */
    return dc_ramp_down(atan2(length(cross(normal, facing)), c), d->angle_fade[0], d->angle_fade[1]);
}

inline float2 dc_frustum_st(__global const DcDecal* d, float3 l) {
    const float half_h = -l.z * d->tan_half_fov_y, half_w = half_h * d->aspect;
    return (float2)(0.5f + l.x / (2.0f * half_w), 0.5f - l.y / (2.0f * half_h));
}

/* A decal's local vector in camera space (the linear part of local_to_camera). */
inline float3 dc_local_vector(__global const DcDecal* d, float3 v) {
    return (float3)(dot(vload3(0, d->local_to_camera), v), dot(vload3(0, d->local_to_camera + 4), v),
                    dot(vload3(0, d->local_to_camera + 8), v));
}

inline float3 dc_decal_origin(__global const DcDecal* d) {
    return (float3)(d->local_to_camera[3], d->local_to_camera[7], d->local_to_camera[11]);
}

/* Where a pixel meets one decal: the texture coordinates (s, t, and r for volumes; `face` for
 * cubes), the same at the pixel's footprint points, and the product of falloff and fades. */
typedef struct {
    float fade; /* 0: the point is outside or faded out */
    float3 coord, coord_dx, coord_dy;
    int face;
    int has_footprint;
    int filtered; /* a pixel-filter tap: textures are integrated over its stratum (coord_dx, coord_dy) */
    int integrated; /* integrated over the whole filter (filter_integral.h): coord_dx, coord_dy one pixel away */
    float3 facing; /* camera-space direction a receiving surface faces */
} DcLookup;

/* Texture coordinates of a decal-local point: (s, t, r) for boxes and volumes, (s, t) on the
 * frustum's image or on cube face `face` (even past its edge, for footprints). */
inline float3 dc_decal_coord(__global const DcDecal* d, float3 l, int face) {
    if (d->kind == DC_KIND_FRUSTUM) return (float3)(dc_frustum_st(d, l), 0.0f);
    if (d->kind == DC_KIND_CUBE) return (float3)(dc_cube_face_st(l, face), 0.0f);
    return (float3)(l.x + 0.5f, 0.5f - l.y, l.z + 0.5f);
}

/* The lookup for the decal at camera-space point p. `normal` is the surface normal (used only
 * when `has_normal`); p_dx and p_dy are the footprint points (used when `footprint`). The
 * rejection comes first and costs one transform: most pixel-decal pairs end there. */
/* Coverage of a tap's stratum by the inside of `inside` >= 0, where the stratum spans `extent`
 * of the same measure: a box filter across a straight edge (0 extent: the hard test). */
inline float dc_soft_inside(float inside, float extent) {
    if (!(extent > 1e-12f)) return inside >= 0.0f ? 1.0f : 0.0f;
    return clamp(inside / extent + 0.5f, 0.0f, 1.0f);
}

/* `soft` (a literal 0 for point samples): p is a pixel-filter tap whose stratum spans the
 * decal-local vectors su, sv; box and frustum edges are then integrated over it. */
DC_INLINE DcLookup dc_decal_lookup_at(__global const DcDecal* d, float3 p, float3 normal, int has_normal, float3 p_dx,
                                      float3 p_dy, int footprint, const int soft, float3 su, float3 sv) {
    DcLookup lk;
    lk.fade = 0.0f;
    lk.face = 0;
    lk.filtered = soft;
    lk.integrated = 0;
    const float3 l = dc_affine_global(d->camera_to_local, p);
    float fade = 1.0f;
    if (d->kind == DC_KIND_BOX || d->kind == DC_KIND_VOLUME) {
        if (soft) {
            const float3 extent = fabs(su) + fabs(sv);
            fade = dc_soft_inside(0.5f - fabs(l.x), extent.x) * dc_soft_inside(0.5f - fabs(l.y), extent.y) *
                   dc_soft_inside(0.5f - fabs(l.z), extent.z);
            if (!(fade > 0.0f)) return lk;
        } else if (!(fabs(l.x) <= 0.5f && fabs(l.y) <= 0.5f && fabs(l.z) <= 0.5f)) {
            return lk;
        }
        if (d->axis_fade > 0.0f) fade *= clamp((0.5f - fabs(l.z)) / (0.5f * d->axis_fade), 0.0f, 1.0f);
        lk.facing = vload3(0, d->facing_axis);
    } else if (d->kind == DC_KIND_FRUSTUM) {
        const float dist = -l.z;
        const float half_h = dist * d->tan_half_fov_y, half_w = half_h * d->aspect;
        if (soft) {
            const float3 extent = fabs(su) + fabs(sv);
            fade = dc_soft_inside(dist - d->near_plane, extent.z) * dc_soft_inside(d->far_plane - dist, extent.z) *
                   dc_soft_inside(half_w - fabs(l.x), extent.x) * dc_soft_inside(half_h - fabs(l.y), extent.y);
            if (!(fade > 0.0f && dist > 0.0f)) return lk;
        } else if (!(dist >= d->near_plane && dist <= d->far_plane && fabs(l.x) <= half_w && fabs(l.y) <= half_h)) {
            return lk;
        }
        if (d->distance_fade[1] > 0.0f) fade *= dc_ramp_down(dist, d->distance_fade[0], d->distance_fade[1]);
        lk.facing = normalize(dc_decal_origin(d) - p);
    } else { /* DC_KIND_CUBE */
        const float r = length(l);
        if (!(r <= 0.5f) || !(r > 0.0f)) return lk;
        fade *= clamp(1.0f - r / 0.5f, 0.0f, 1.0f);
        lk.facing = normalize(dc_decal_origin(d) - p);
        lk.face = dc_cube_face(l);
    }
    if (has_normal && d->angle_fade[1] > 0.0f) fade *= dc_angle_fade(d, normal, lk.facing);
    lk.coord = dc_decal_coord(d, l, lk.face);
    lk.coord_dx = lk.coord_dy = lk.coord;
    if (soft) {
        lk.has_footprint = 1;
        lk.coord_dx = dc_decal_coord(d, l + su, lk.face);
        lk.coord_dy = dc_decal_coord(d, l + sv, lk.face);
    } else {
        lk.has_footprint = footprint && d->filter == DC_FILTER_MIP;
        if (lk.has_footprint) {
            lk.coord_dx = dc_decal_coord(d, dc_affine_global(d->camera_to_local, p_dx), lk.face);
            lk.coord_dy = dc_decal_coord(d, dc_affine_global(d->camera_to_local, p_dy), lk.face);
        }
    }
    lk.fade = fade;
    return lk;
}

/* The point-sampled lookup at the pixel centre. */
DC_INLINE DcLookup dc_decal_lookup(__global const DcDecal* d, float3 p, float3 normal, int has_normal, float3 p_dx,
                                   float3 p_dy, int footprint) {
    return dc_decal_lookup_at(d, p, normal, has_normal, p_dx, p_dy, footprint, 0, (float3)(0.0f), (float3)(0.0f));
}

/* One texture of the decal's set at the lookup's coordinates, with the decal's filter;
 * premultiplied RGBA. Mip levels come from the footprint mapped the same way. */
DC_INLINE float4 dc_lookup_texel(__global const DcDecal* d, DcLookup lk, __global const DcTexture* textures,
                                 __global const float4* texels, int index, const int variant) {
    const float3 c = lk.coord;
    const bool flat = (variant & DC_VARIANT_FLAT) != 0;
    /* A filter tap integrates its stratum: nearest texels exactly over strata up to two texels
     * wide (dc_sample_slice_box), every other case reads the mip chain at the stratum's size. */
    const int filter = lk.filtered ? DC_FILTER_MIP : d->filter;
    if (lk.filtered && d->filter == DC_FILTER_NEAREST && (flat || (d->kind != DC_KIND_VOLUME && d->kind != DC_KIND_CUBE))) {
        const DcTexture t = textures[index];
        const float2 size = (float2)((float)t.width, (float)t.height);
        const float2 rho = (fabs(lk.coord_dx.xy - c.xy) + fabs(lk.coord_dy.xy - c.xy)) * size;
        if (rho.x <= 2.0f && rho.y <= 2.0f) return dc_sample_slice_box(texels, t, c.x, c.y, 0, rho);
    }
    if (!flat && d->kind == DC_KIND_VOLUME) {
        if (filter != DC_FILTER_MIP) return dc_sample_3d(texels, textures[index], c.x, c.y, c.z, filter);
        /* quadrilinear in the volume's 3D mip chain; (s, t, r) moves with local space up to a sign */
        const float lod = lk.has_footprint ? dc_lod_volume(c, lk.coord_dx, lk.coord_dy, textures[index]) : 1e9f;
        return dc_sample_chain(texels, textures, index, c.x, c.y, c.z, 0, lod, DC_LEVEL_VOLUME);
    }
    const int cube = !flat && d->kind == DC_KIND_CUBE;
    if (filter == DC_FILTER_MIP) {
        const float lod = lk.has_footprint ? dc_lod(c.xy, lk.coord_dx.xy, lk.coord_dy.xy, textures[index]) : 1e9f;
        return dc_sample_chain(texels, textures, index, c.x, c.y, 0.0f, lk.face, lod,
                               cube ? DC_LEVEL_CUBE : DC_LEVEL_SLICE);
    }
    return cube ? dc_sample_cube_face(texels, textures[index], c.x, c.y, lk.face, filter)
                : dc_sample_slice(texels, textures[index], c.x, c.y, 0, filter);
}

/* Camera-space directions in which s grows and t falls (the image's right and up) at the
 * lookup: the decal's local X and Y, or a cube face's axes (faces seen from inside are
 * mirrored, so the frame built from them may be left-handed, as the image is). */
inline void dc_decal_image_axes(__global const DcDecal* d, DcLookup lk, float3* right, float3* up) {
    float3 r = (float3)(1.0f, 0.0f, 0.0f), u = (float3)(0.0f, 1.0f, 0.0f);
    if (d->kind == DC_KIND_CUBE) {
        switch (lk.face) {
            case 0:
                r = (float3)(0.0f, 0.0f, -1.0f);
                break;
            case 1:
                r = (float3)(0.0f, 0.0f, 1.0f);
                break;
            case 2:
                u = (float3)(0.0f, 0.0f, -1.0f);
                break;
            case 3:
                u = (float3)(0.0f, 0.0f, 1.0f);
                break;
            case 4:
                break;
            default:
                r = (float3)(-1.0f, 0.0f, 0.0f);
                break;
        }
    }
    *right = dc_local_vector(d, r);
    *up = dc_local_vector(d, u);
}

#endif
