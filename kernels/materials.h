/* Blending a decal's texture set into a pixel's material (docs/conventions.md "Materials"):
 * per-target factors and blend ops, and normal maps in a tangent frame built on the surface. */
#ifndef DECALCOMP_MATERIALS_H
#define DECALCOMP_MATERIALS_H

#include "shared_types.h"
#include "decal_kinds.h"
#include "filter_integral.h"

/* A pixel's material while decals are applied; the normal is in camera space. */
typedef struct {
    float3 albedo, normal, emission;
    float roughness, metallic, ao;
    int normal_changed;
} DcSurface;

/* acc + w * s, field by field: the pixel filter's weighted sum of its taps' materials. */
inline DcSurface dc_surface_add_scaled(DcSurface acc, DcSurface s, float w) {
    acc.albedo += s.albedo * w;
    acc.normal += s.normal * w;
    acc.emission += s.emission * w;
    acc.roughness += s.roughness * w;
    acc.metallic += s.metallic * w;
    acc.ao += s.ao * w;
    acc.normal_changed |= s.normal_changed;
    return acc;
}

inline float3 dc_blend3(float3 a, float3 v, float f, float g, int op) {
    switch (op) {
        case DC_OP_MULTIPLY:
            return a * (1.0f - f) + a * v * f;
        case DC_OP_ADD:
            return a + v * g;
        case DC_OP_REPLACE:
            return v;
        default:
            return a * (1.0f - f) + v * f;
    }
}

inline float dc_blend1(float a, float v, float f, float g, int op) {
    return dc_blend3((float3)(a), (float3)(v), f, g, op).x;
}

/* Straight colour of a premultiplied texel; false where it is fully transparent. */
inline bool dc_straight(float4 texel, float3* out) {
    if (!(texel.w > 0.0f)) return false;
    *out = texel.xyz / texel.w;
    return true;
}

/* Combines base normal b with detail d, both unit vectors in a tangent frame (z = the frame's
 * normal): reoriented normal mapping, UDN, whiteout, or d alone. */
inline float3 dc_combine_normals(float3 b, float3 d, int mode) {
    switch (mode) {
        case DC_NORMAL_UDN:
            return normalize((float3)(b.x + d.x, b.y + d.y, b.z));
        case DC_NORMAL_WHITEOUT:
            return normalize((float3)(b.x + d.x, b.y + d.y, b.z * d.z));
        case DC_NORMAL_REPLACE:
            return d;
        default: {
            const float3 t = b + (float3)(0.0f, 0.0f, 1.0f);
            if (!(t.z > 1e-6f)) return d; /* base points straight into the surface */
            const float3 u = (float3)(-d.x, -d.y, d.z);
            return normalize(t * (dot(t, u) / t.z) - u);
        }
    }
}

/* Orthonormal frame (t, b, n) whose t and b follow the image's right and up projected onto
 * the plane of n; false when the image's right direction is (nearly) along n. */
inline bool dc_tangent_frame(float3 n, float3 right, float3 up, float3* t, float3* b) {
    const float3 tt = right - n * dot(n, right);
    if (!(length(tt) > 1e-2f * length(right))) return false;
    *t = normalize(tt);
    const float3 bb = up - n * dot(n, up) - *t * dot(*t, up);
    if (!(length(bb) > 1e-2f * length(up))) return false;
    *b = normalize(bb);
    return true;
}

/* The decal's normal map texel applied to s.normal with blend factor f. `surface_normal` is
 * the G-buffer's own normal (camera space), the frame's z unless the mode is replace. */
DC_INLINE DcSurface dc_apply_normal_map(__global const DcDecal* d, DcLookup lk, float4 texel, float3 surface_normal,
                                        float f, DcSurface s) {
    float3 rgb;
    if (!dc_straight(texel, &rgb)) return s;
    float3 detail = rgb * 2.0f - 1.0f;
    detail.xy *= d->normal_strength;
    if (!(length(detail) > 1e-6f)) return s;
    detail = normalize(detail);
    const float3 n = d->normal_blend == DC_NORMAL_REPLACE ? lk.facing : surface_normal;
    float3 right, up, t, b;
    dc_decal_image_axes(d, lk, &right, &up);
    if (!dc_tangent_frame(n, right, up, &t, &b)) return s;
    const float3 base = (float3)(dot(s.normal, t), dot(s.normal, b), dot(s.normal, n));
    const float3 r = dc_combine_normals(base, detail, d->normal_blend);
    const float3 mapped = t * r.x + b * r.y + n * r.z;
    const float3 mixed = s.normal * (1.0f - f) + mapped * f;
    s.normal = length(mixed) > 1e-6f ? normalize(mixed) : mapped;
    s.normal_changed = 1;
    return s;
}

/* A colour target's value: the decal's constant when it has one (the texture then only shapes
 * the coverage), else the texture's straight colour. */
inline bool dc_value3(__global const DcDecal* d, int target, __global const float* fixed, int texture, float4 texel,
                      float3* v) {
    if (d->value_mask & (1 << target)) {
        *v = vload3(0, fixed);
        return true;
    }
    return texture >= 0 && dc_straight(texel, v);
}

inline bool dc_targets(__constant const DcFrame* frame, __global const DcDecal* d, int target) {
    return (frame->attributes & (1 << target)) && d->factor[target] > 0.0f;
}

/* A texture set's coverage: the albedo's alpha; without an albedo, the first texture of the set's
 * (also what a UV-space bake stores, kernels/bake.cl). */
inline float dc_set_coverage(__global const DcDecal* d, float4 albedo, float4 normal, float4 orm, float4 emission) {
    return d->texture >= 0            ? albedo.w
           : d->normal_texture >= 0   ? normal.w
           : d->orm_texture >= 0      ? orm.w
           : d->emission_texture >= 0 ? emission.w
                                      : 1.0f;
}

/* One texture of the decal's set at the lookup: integrated over the pixel filter, or read as
 * dc_lookup_texel reads it. */
DC_INLINE float4 dc_set_texel(__constant const DcFrame* frame, __global const DcDecal* d, DcLookup lk,
                              __global const DcTexture* textures, __global const float4* texels, int index,
                              const int variant) {
    return lk.integrated ? dc_integrated_texel(frame, d, lk, textures, texels, index, variant)
                         : dc_lookup_texel(d, lk, textures, texels, index, variant);
}

/* Blends one decal into the surface. `weight` is opacity times mask; `surface_normal` the
 * G-buffer's normal in camera space (valid when the frame has normals). `variant` (DC_VARIANT_x, a
 * literal per kernel) compiles away what the kernel excludes. */
DC_INLINE DcSurface dc_apply_decal(__constant const DcFrame* frame, __global const DcDecal* d, DcLookup lk,
                                   __global const DcTexture* textures, __global const float4* texels, float weight,
                                   float3 surface_normal, DcSurface s, const int variant) {
    const bool albedo_only = (variant & DC_VARIANT_ALBEDO_ONLY) != 0;
    const bool want_albedo = dc_targets(frame, d, DC_TARGET_ALBEDO);
    const bool want_normal = !albedo_only && dc_targets(frame, d, DC_TARGET_NORMAL) && d->normal_texture >= 0;
    const bool want_orm = !albedo_only && d->orm_texture >= 0 &&
                          (dc_targets(frame, d, DC_TARGET_ROUGHNESS) || dc_targets(frame, d, DC_TARGET_METALLIC) ||
                           dc_targets(frame, d, DC_TARGET_AO));
    const bool want_emission = !albedo_only && dc_targets(frame, d, DC_TARGET_EMISSION);
    /* Coverage is the albedo's alpha; without an albedo, the first texture of the set's. */
    float4 albedo = (float4)(0.0f), normal = (float4)(0.0f), orm = (float4)(0.0f), emission = (float4)(0.0f);
    if (d->texture >= 0) albedo = dc_set_texel(frame, d, lk, textures, texels, d->texture, variant);
    if (want_normal || (d->texture < 0 && d->normal_texture >= 0))
        normal = dc_set_texel(frame, d, lk, textures, texels, d->normal_texture, variant);
    if (want_orm || (d->texture < 0 && d->normal_texture < 0 && d->orm_texture >= 0))
        orm = dc_set_texel(frame, d, lk, textures, texels, d->orm_texture, variant);
    if (d->emission_texture >= 0 && (want_emission || (d->texture < 0 && d->normal_texture < 0 && d->orm_texture < 0)))
        emission = dc_set_texel(frame, d, lk, textures, texels, d->emission_texture, variant);
    const float coverage = dc_set_coverage(d, albedo, normal, orm, emission);
    const float g = coverage * lk.fade * weight; /* before each target's factor */
    if (!(g > 0.0f)) return s;
    float3 v;
    if (want_albedo && dc_value3(d, DC_TARGET_ALBEDO, d->albedo_value, d->texture, albedo, &v)) {
        const float gt = g * d->factor[DC_TARGET_ALBEDO];
        s.albedo = dc_blend3(s.albedo, v, clamp(gt, 0.0f, 1.0f), gt, d->op[DC_TARGET_ALBEDO]);
    }
    if (want_normal)
        s = dc_apply_normal_map(d, lk, normal, surface_normal, clamp(g * d->factor[DC_TARGET_NORMAL], 0.0f, 1.0f), s);
    const bool orm_ok = d->orm_texture >= 0 && dc_straight(orm, &v);
    const float3 orm_value = v;
    for (int target = DC_TARGET_ROUGHNESS; target <= DC_TARGET_AO && !albedo_only; ++target) {
        if (!dc_targets(frame, d, target)) continue;
        float value;
        if (d->value_mask & (1 << target)) {
            value = target == DC_TARGET_AO          ? d->ao_value
                    : target == DC_TARGET_ROUGHNESS ? d->roughness_value
                                                    : d->metallic_value;
        } else if (orm_ok) {
            value = target == DC_TARGET_AO ? orm_value.x : target == DC_TARGET_ROUGHNESS ? orm_value.y : orm_value.z;
        } else {
            continue;
        }
        const float gt = g * d->factor[target], f = clamp(gt, 0.0f, 1.0f);
        if (target == DC_TARGET_AO)
            s.ao = dc_blend1(s.ao, value, f, gt, d->op[target]);
        else if (target == DC_TARGET_ROUGHNESS)
            s.roughness = dc_blend1(s.roughness, value, f, gt, d->op[target]);
        else
            s.metallic = dc_blend1(s.metallic, value, f, gt, d->op[target]);
    }
    if (want_emission && dc_value3(d, DC_TARGET_EMISSION, d->emission_value, d->emission_texture, emission, &v)) {
        const float gt = g * d->factor[DC_TARGET_EMISSION];
        s.emission = dc_blend3(s.emission, v, clamp(gt, 0.0f, 1.0f), gt, d->op[DC_TARGET_EMISSION]);
    }
    return s;
}

#endif
