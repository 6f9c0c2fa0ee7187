/* The beauty follows the decals (docs/profiles.md "Beauty"): at a pixel some decal changed,
 *   beauty' = beauty + sum over the albedo lobe's light terms of light * (albedo' - albedo)
 * for light divided by its colour (Blender), or light * (albedo' / albedo - 1) for light multiplied
 * by it (Arnold, RenderMan, V-Ray), whose terms are rewritten to light * albedo' / albedo; emission
 * changes add as they are. Opt-in relighting scales the direct terms by the ratio of a Lambert fit
 * with the new and the old normal. The beauty's alpha is not here: it never changes. */
#ifndef DECALCOMP_BEAUTY_H
#define DECALCOMP_BEAUTY_H

#include "reconstruct.h"
#include "shared_types.h"

/* Mixed pixels of a filtered frame (docs/profiles.md "Mixed pixels"): a normal pass shorter than
 * DC_MIXED_NORMAL_LENGTH (the filter averaged differing normals), a background 4-neighbour, or one
 * more than DC_MIXED_DEPTH_JUMP away in relative view depth. */

/* 0 for a pixel that is not mixed; else the surface pixels of its 3 x 3 neighbourhood, bit
 * 3 (dy + 1) + (dx + 1), itself included. */
inline uint dc_mixed_surfaces(__constant const DcFrame* f, __global const float* depth_plane,
                              __global const float4* position_plane, int x, int y, float view_depth,
                              float3 normal_pass) {
    bool mixed = f->has_normal && !f->reconstruct_normals && length(normal_pass) < DC_MIXED_NORMAL_LENGTH;
    uint surfaces = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= f->width || ny >= f->height) continue;
            float z = view_depth;
            const bool surface = (dx == 0 && dy == 0) || dc_view_depth(f, depth_plane, position_plane, nx, ny, &z);
            if (surface) surfaces |= 1u << (3 * (dy + 1) + dx + 1);
            if (dx != 0 && dy != 0) continue; /* the jump and background tests take 4-neighbours */
            if (!surface || fabs(z - view_depth) > DC_MIXED_DEPTH_JUMP * view_depth) mixed = true;
        }
    return mixed ? surfaces : 0u;
}

/* A light term at a mixed pixel (`term`: the pixel's index in the packed terms, `own` its value,
 * already loaded): per channel, the least of its own and its surface neighbours'. Where a
 * decal's change has one sign over the footprint, the filtered truth sum(w L delta) lies between
 * the least and the most light times the filtered change, so the least never overshoots it and
 * the pixel cannot end up further from the truth than the untouched beauty. */
inline float3 dc_least_light(float3 own, __global const float* light, size_t term, int width, uint surfaces) {
    float3 least = own;
    for (int k = 0; k < 9; ++k)
        if (k != 4 && (surfaces & (1u << k)))
            least = fmin(least, vload3((long)term + (long)(k / 3 - 1) * width + (k % 3 - 1), light));
    return least;
}

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

/* The beauty's change at a changed pixel; the host adds it to the beauty (beauty_transfer.hpp), so
 * the kernel never reads the beauty: at a changed pixel its traffic is the terms' reads alone, not
 * the beauty read and written besides. `mixed_surfaces` (dc_mixed_surfaces, or 0): at a mixed pixel
 * divided light takes the least light around it (dc_least_light). Only divided light without
 * relighting reads its neighbours: those terms are never written, so no other work-item changes them
 * meanwhile. Each term is packed RGB. `l0` and `l1`: the first two terms at the pixel, loaded by
 * the caller before its decal loop (their latency hid behind it: on an H100 the update's cost at
 * 1080p with 1024 decals fell from 0.036 to 0.032 ms, docs/benchmarks.md); the kernel cannot load
 * them here ahead of the stores below, which may write the same buffer. */
inline float3 dc_beauty_change(__constant const DcFrame* f, size_t i, size_t pixels, float3 albedo_before,
                               float3 albedo_after, float3 emission_delta, float relight, uint mixed_surfaces,
                               __global float* light, float3 l0, float3 l1) {
    float3 add = f->beauty_emission ? emission_delta : (float3)(0.0f);
    if (all(albedo_after == albedo_before) && relight == 1.0f) return add;
    const int terms = f->light_terms;
    /* the colour's ratio (three divisions) only for multiplied light, which alone uses it */
    const float3 delta = albedo_after - albedo_before;
    const float3 ratio = f->light_divided ? (float3)(1.0f) : dc_colour_ratio(albedo_before, albedo_after);
    for (int t = 0; t < terms; ++t) {
        const size_t term = (size_t)t * pixels + i;
        const float3 own = t == 0 ? l0 : t == 1 ? l1 : vload3(term, light);
        const float3 l = mixed_surfaces != 0 ? dc_least_light(own, light, term, f->width, mixed_surfaces) : own;
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
        if (f->light_divided ? scale != 1.0f : 1) vstore3(rewritten, term, light);
    }
    return add;
}

#endif
