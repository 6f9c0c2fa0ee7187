/* Per-kind projection of a camera-space point into a decal (docs/conventions.md "Decals"):
 * the inside test, texture lookup and the kind's own falloff and fades. */
#ifndef DECALCOMP_DECAL_KINDS_H
#define DECALCOMP_DECAL_KINDS_H

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

/* A 2D lookup with the decal's filter; for mip filtering the level comes from where the
 * neighbour pixels' footprint points (local lx, ly) map to, through the same `st` mapping. */
#define DC_SAMPLE_2D(ST_OF)                                                                              \
    do {                                                                                                 \
        const float2 st = ST_OF(l);                                                                      \
        if (d->filter == DC_FILTER_MIP) {                                                                \
            const float3 lx = dc_affine_global(d->camera_to_local, p_dx);                                \
            const float3 ly = dc_affine_global(d->camera_to_local, p_dy);                                \
            const float lod = footprint ? dc_lod(st, ST_OF(lx), ST_OF(ly), textures[d->texture]) : 1e9f; \
            texel = dc_sample_mip(texels, textures, d->texture, st.x, st.y, 0, lod);                     \
        } else {                                                                                         \
            texel = dc_sample_2d(texels, textures[d->texture], st.x, st.y, d->filter);                   \
        }                                                                                                \
    } while (0)
#define DC_BOX_ST(v) ((float2)((v).x + 0.5f, 0.5f - (v).y))
#define DC_FRUSTUM_ST(v) dc_frustum_st(d, (v))

/* Returns the decal's premultiplied colour at p with alpha scaled by the kind's falloff and every
 * fade, or alpha 0 when p is outside. `normal` is the camera-space surface normal (used only
 * when `has_normal`); p_dx and p_dy are the footprint points (used when `footprint`). */
inline float4 dc_decal_colour(__global const DcDecal* d, __global const DcTexture* textures,
                              __global const float4* texels, float3 p, float3 normal, int has_normal, float3 p_dx,
                              float3 p_dy, int footprint) {
    const float3 l = dc_affine_global(d->camera_to_local, p);
    float fade = 1.0f;
    float4 texel;
    const bool angle_fade = has_normal && d->angle_fade[1] > 0.0f;
    if (d->kind == DC_KIND_BOX || d->kind == DC_KIND_VOLUME) {
        if (!(fabs(l.x) <= 0.5f && fabs(l.y) <= 0.5f && fabs(l.z) <= 0.5f)) return (float4)(0.0f);
        if (d->axis_fade > 0.0f) fade *= clamp((0.5f - fabs(l.z)) / (0.5f * d->axis_fade), 0.0f, 1.0f);
        if (angle_fade) fade *= dc_angle_fade(d, normal, vload3(0, d->facing_axis));
        if (d->texture < 0) return (float4)(0.0f);
        if (d->kind == DC_KIND_BOX)
            DC_SAMPLE_2D(DC_BOX_ST);
        else if (d->filter == DC_FILTER_MIP) { /* quadrilinear in the volume's 3D mip chain */
            const float lod = footprint
                                  ? dc_lod_volume(l, dc_affine_global(d->camera_to_local, p_dx),
                                                  dc_affine_global(d->camera_to_local, p_dy), textures[d->texture])
                                  : 1e9f;
            texel = dc_sample_chain(texels, textures, d->texture, l.x + 0.5f, 0.5f - l.y, l.z + 0.5f, 0, lod,
                                    DC_LEVEL_VOLUME);
        } else {
            texel = dc_sample_3d(texels, textures[d->texture], l.x + 0.5f, 0.5f - l.y, l.z + 0.5f, d->filter);
        }
    } else if (d->kind == DC_KIND_FRUSTUM) {
        const float dist = -l.z;
        const float half_h = dist * d->tan_half_fov_y, half_w = half_h * d->aspect;
        if (!(dist >= d->near_plane && dist <= d->far_plane && fabs(l.x) <= half_w && fabs(l.y) <= half_h))
            return (float4)(0.0f);
        if (d->distance_fade[1] > 0.0f) fade *= dc_ramp_down(dist, d->distance_fade[0], d->distance_fade[1]);
        if (angle_fade) {
            const float3 origin = (float3)(d->local_to_camera[3], d->local_to_camera[7], d->local_to_camera[11]);
            fade *= dc_angle_fade(d, normal, normalize(origin - p));
        }
        if (d->texture < 0) return (float4)(0.0f);
        DC_SAMPLE_2D(DC_FRUSTUM_ST);
    } else { /* DC_KIND_CUBE */
        const float r = length(l);
        if (!(r <= 0.5f)) return (float4)(0.0f);
        fade *= clamp(1.0f - r / 0.5f, 0.0f, 1.0f);
        if (angle_fade) {
            const float3 centre = (float3)(d->local_to_camera[3], d->local_to_camera[7], d->local_to_camera[11]);
            fade *= dc_angle_fade(d, normal, normalize(centre - p));
        }
        if (d->texture < 0 || !(r > 0.0f)) return (float4)(0.0f);
        const int face = dc_cube_face(l);
        const float2 st = dc_cube_face_st(l, face);
        if (d->filter == DC_FILTER_MIP) {
            const float3 lx = dc_affine_global(d->camera_to_local, p_dx), ly = dc_affine_global(d->camera_to_local, p_dy);
            const float lod = footprint ? dc_lod(st, dc_cube_face_st(lx, face), dc_cube_face_st(ly, face), textures[d->texture])
                                        : 1e9f;
            texel = dc_sample_chain(texels, textures, d->texture, st.x, st.y, 0.0f, face, lod, DC_LEVEL_CUBE);
        } else {
            texel = dc_sample_cube_face(texels, textures[d->texture], st.x, st.y, face, d->filter);
        }
    }
    return texel * fade;
}

#undef DC_SAMPLE_2D
#undef DC_BOX_ST
#undef DC_FRUSTUM_ST

#endif
