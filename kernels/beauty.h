/* The beauty follows the decals (docs/profiles.md "Beauty"): at a pixel some decal changed,
 *   beauty' = beauty + sum over the albedo lobe's light terms of light * (albedo' - albedo)
 * for light divided by its colour (Blender), or light * (albedo' / albedo - 1) for light multiplied
 * by it (Arnold, RenderMan, V-Ray), whose terms are rewritten to light * albedo' / albedo; emission
 * changes add as they are. Opt-in relighting scales the direct terms by the ratio of a Lambert fit
 * with the new and the old normal. The beauty's alpha is not here: it never changes. */
#ifndef DECALCOMP_BEAUTY_H
#define DECALCOMP_BEAUTY_H

#include "shared_types.h"

/* Ratio of the fitted direct light with the new and the old world normal; 1 where the fit sees
 * no light from the old normal (it cannot say what the new one receives). */
inline float dc_relight_ratio(__constant const DcFrame* f, float3 n_before, float3 n_after) {
    const float3 c = vload3(0, f->light_fit);
    const float before = f->light_fit[3] + dot(c, n_before);
    const float after = f->light_fit[3] + dot(c, n_after);
    if (!(before > 1e-3f)) return 1.0f;
    return clamp(after / before, 0.0f, 4.0f);
}

/* Multiplied light: the colour's ratio per channel; where the old colour is 0 the light it
 * carried is unknown, so the term stays (and the beauty with it). */
inline float3 dc_colour_ratio(float3 before, float3 after) {
    return (float3)(before.x > 0.0f ? after.x / before.x : 1.0f, before.y > 0.0f ? after.y / before.y : 1.0f,
                    before.z > 0.0f ? after.z / before.z : 1.0f);
}

inline void dc_update_beauty(__constant const DcFrame* f, size_t i, size_t pixels, float3 albedo_before,
                             float3 albedo_after, float3 emission_delta, float relight, __global float4* beauty,
                             __global float4* light) {
    /* The loads first, so that their latencies overlap (the compiler cannot move them past the
     * stores below), and whole-float4 stores: on an H200 the update cost 0.13 ms at 1080p with 1024
     * decals written in place term by term, 0.09 ms so (docs/benchmarks.md "Beauty update"). */
    const float4 b = beauty[i];
    const int terms = f->light_terms;
    const float4 l0 = terms > 0 ? light[i] : (float4)(0.0f);
    const float4 l1 = terms > 1 ? light[pixels + i] : (float4)(0.0f);
    float3 add = f->beauty_emission ? emission_delta : (float3)(0.0f);
    if (!all(albedo_after == albedo_before) || relight != 1.0f) {
        const float3 delta = albedo_after - albedo_before, ratio = dc_colour_ratio(albedo_before, albedo_after);
        for (int t = 0; t < terms; ++t) {
            __global float4* term = light + (size_t)t * pixels + i;
            const float4 l4 = t == 0 ? l0 : t == 1 ? l1 : *term;
            const float3 l = l4.xyz;
            const float scale = t < f->direct_terms ? relight : 1.0f;
            float3 change, rewritten = l;
            if (f->light_divided) {
                /* one product for the plain case, so the update is exact to one rounding */
                change = scale == 1.0f ? l * delta : l * scale * albedo_after - l * albedo_before;
                if (scale != 1.0f) rewritten = l * scale;
            } else {
                rewritten = l * (ratio * scale);
                change = rewritten - l;
            }
            if (t < f->summed_terms) add += change;
            if (f->light_divided ? scale != 1.0f : 1) *term = (float4)(rewritten, l4.w);
        }
    }
    if (add.x != 0.0f || add.y != 0.0f || add.z != 0.0f) beauty[i] = (float4)(b.xyz + add, b.w);
}

#endif
