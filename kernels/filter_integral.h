/* Decals integrated over the renderer's pixel filter in closed form, for pixels on one tangent
 * plane (docs/pixel-filter.md "Integrated evaluation"): the pixel's offsets (u, v) map affinely to
 * decal-local points, each straight edge (a face of the volume, a texel's border) covers the
 * filter's edge-spread share, and nearest texels are weighted by the filter's share of their cell. */
#ifndef DECALCOMP_FILTER_INTEGRAL_H
#define DECALCOMP_FILTER_INTEGRAL_H

#include "shared_types.h"
#include "decal_kinds.h"
#include "texture_sample.h"

/* The filter's edge-spread function across the edges of a quantity a changing by g per pixel
 * offset (u, v): its row of the table (pixel_filter.hpp edgeSpreadFromTable, the host's copy of
 * this interpolation) and the scale from a's units to the table's distances. */
typedef struct {
    float scale, fk;
    __constant const float* row;
} DcEdgeSpread;

/* How far from a0 the edge-spread of a quantity a = a0 + g . (u, v) reaches: filter_radius (|g.u| +
 * |g.v|), in a's units. */
inline float dc_edge_reach(__constant const DcFrame* f, float2 g) {
    return f->filter_radius * (fabs(g.x) + fabs(g.y));
}

inline DcEdgeSpread dc_edge_spread_along(__constant const DcFrame* f, float2 g) {
    const float a = fmax(fabs(g.x), fabs(g.y)), b = fmin(fabs(g.x), fabs(g.y));
    DcEdgeSpread e;
    e.scale = 1.0f / dc_edge_reach(f, g); /* infinite for a flat quantity: the hard test */
    const float rk = a > 0.0f ? b / a * (float)(DC_EDGE_SPREAD_RATIOS - 1) : 0.0f;
    const int k = min((int)rk, DC_EDGE_SPREAD_RATIOS - 2);
    e.fk = rk - (float)k;
    e.row = f->filter_edge + k * DC_EDGE_SPREAD_STEPS;
    return e;
}

/* The share on the side a <= a0 + delta. */
DC_CPU_INLINE float dc_edge_share(const DcEdgeSpread* e, float delta) {
    const float t = delta * e->scale;
    if (!(fabs(t) < 1.0f)) return t > 0.0f ? 1.0f : 0.0f;
    const float sj = fabs(t) * (float)(DC_EDGE_SPREAD_STEPS - 1);
    const int j = min((int)sj, DC_EDGE_SPREAD_STEPS - 2);
    const float fj = sj - (float)j;
    __constant const float* v = e->row + j;
    const float share = mix(mix(v[0], v[1], fj), mix(v[DC_EDGE_SPREAD_STEPS], v[DC_EDGE_SPREAD_STEPS + 1], fj), e->fk);
    return t >= 0.0f ? share : 1.0f - share;
}

/* The filter's share where lo <= a <= hi, a = a0 + g . (u, v). */
DC_CPU_INLINE float dc_slab_share(__constant const DcFrame* f, float a0, float2 g, float lo, float hi) {
    /* the footprint wholly inside or outside: no table */
    const float reach = dc_edge_reach(f, g);
    if (a0 - reach >= lo && a0 + reach <= hi) return 1.0f;
    if (a0 + reach <= lo || a0 - reach >= hi) return 0.0f;
    const DcEdgeSpread e = dc_edge_spread_along(f, g);
    return fmax(0.0f, dc_edge_share(&e, hi - a0) - dc_edge_share(&e, lo - a0));
}

/* Texels per axis an integrated read weights one by one; wider footprints read a coarser level. */
#define DC_INTEGRATED_TEXELS 12

/* The texel columns [i, i + 1) that the texel coordinate c0 + g . (u, v) crosses: `count` of them
 * from `first`. dc_texel_share_below gives the shares. */
typedef struct {
    DcEdgeSpread e;
    float c0;
    int first, count;
} DcTexelSpan;

inline DcTexelSpan dc_texel_span(__constant const DcFrame* f, float c0, float2 g, int size) {
    const float reach = dc_edge_reach(f, g);
    DcTexelSpan span;
    span.first = (int)dc_floor_clamped(clamp(c0 - reach, 0.0f, (float)size - 1.0f));
    const int last = min((int)dc_floor_clamped(clamp(c0 + reach, 0.0f, (float)size - 1.0f)),
                         span.first + DC_INTEGRATED_TEXELS - 1);
    span.count = last - span.first + 1;
    span.e = dc_edge_spread_along(f, g);
    span.c0 = c0;
    return span;
}

/* The share below column `i` of the span's (its left edge's edge-spread share). On GPUs the shares
 * are computed as they are read, not kept in an array: a private array indexed by a loop variable
 * lives in memory there (a 96-byte stack slot per array and texture). */
inline float dc_texel_share_below(const DcTexelSpan* span, int i) {
    return dc_edge_share(&span->e, (float)(span->first + i) - span->c0);
}

/* A nearest-filtered 2D texture (a slice) integrated over the filter: texture coordinates st with
 * steps st_u, st_v per pixel offset; zero beyond the texture's edges, which are the decal's. The
 * filter's shares along s and t multiply (exact for texture axes along the pixel grid). */
DC_INLINE float4 dc_integrate_slice(__constant const DcFrame* f, __global const float4* texels,
                                    __global const DcTexture* textures, int index, float2 st, float2 st_u,
                                    float2 st_v, int slice) {
    /* the level whose texels the footprint crosses at most DC_INTEGRATED_TEXELS per axis */
    const DcTexture base = textures[index];
    float span = 2.0f * f->filter_radius *
                 fmax((fabs(st_u.x) + fabs(st_v.x)) * (float)base.width, (fabs(st_u.y) + fabs(st_v.y)) * (float)base.height);
    int level = 0;
    while (span > (float)(DC_INTEGRATED_TEXELS - 1) && level < base.levels - 1) {
        span *= 0.5f;
        ++level;
    }
    const DcTexture t = textures[index + level];
    const float2 size = (float2)((float)t.width, (float)t.height);
    const DcTexelSpan ss = dc_texel_span(f, st.x * size.x, (float2)(st_u.x, st_v.x) * size.x, t.width);
    const DcTexelSpan ts = dc_texel_span(f, st.y * size.y, (float2)(st_u.y, st_v.y) * size.y, t.height);
    /* the spans lie within the texture (dc_texel_span): rows are read without clamping */
    __global const float4* first_row =
        texels + t.offset + (clamp(slice, 0, t.depth - 1) * t.height + ts.first) * t.width + ss.first;
#ifdef DC_CPU_DEVICE
    /* scalar work-items: each column's share once, not once per row (PoCL: `:fast` 5 % faster) */
    float column_share[DC_INTEGRATED_TEXELS];
    float below_column = dc_texel_share_below(&ss, 0);
    for (int i = 0; i < ss.count; ++i) {
        const float next = dc_texel_share_below(&ss, i + 1);
        column_share[i] = next - below_column;
        below_column = next;
    }
#endif
    float4 sum = (float4)(0.0f);
    float below_t = dc_texel_share_below(&ts, 0);
    for (int j = 0; j < ts.count; ++j) {
        const float next_t = dc_texel_share_below(&ts, j + 1), share_t = next_t - below_t;
        below_t = next_t;
        if (!(share_t > 0.0f)) continue;
        __global const float4* texel_row = first_row + j * t.width;
        float4 row = (float4)(0.0f);
#ifdef DC_CPU_DEVICE
        for (int i = 0; i < ss.count; ++i) row += texel_row[i] * column_share[i];
#else
        float below_s = dc_texel_share_below(&ss, 0);
        for (int i = 0; i < ss.count; ++i) {
            const float next_s = dc_texel_share_below(&ss, i + 1);
            row += texel_row[i] * (next_s - below_s);
            below_s = next_s;
        }
#endif
        sum += row * share_t;
    }
    return sum;
}

/* Whether a decal's texels carry its side edges (box and frustum decals with nearest 2D textures:
 * the texture's edges are the volume's or the projector's sides). */
inline bool dc_texel_edges(__global const DcDecal* d) {
    return (d->kind == DC_KIND_BOX || d->kind == DC_KIND_FRUSTUM) && d->filter == DC_FILTER_NEAREST &&
           (d->texture >= 0 || d->normal_texture >= 0 || d->orm_texture >= 0 || d->emission_texture >= 0);
}

/* The lookup of decal d integrated over the filter on a tangent plane: local point l at the pixel
 * centre moving by lu, lv per pixel offset, camera-space point p with unit normal n. Side edges
 * that texels carry are left to the texture reads (dc_integrated_texel); the other faces cover
 * their edge-spread share; fades are taken at the centre. */
DC_INLINE DcLookup dc_decal_lookup_integrated(__constant const DcFrame* f, __global const DcDecal* d, float3 l,
                                              float3 lu, float3 lv, float3 p, float3 n, int has_normal) {
    DcLookup lk;
    lk.fade = 0.0f;
    lk.face = 0;
    lk.filtered = 1;
    lk.integrated = 1;
    lk.has_footprint = 1;
    const bool texel_edges = dc_texel_edges(d);
    float fade = 1.0f;
    if (d->kind == DC_KIND_BOX || d->kind == DC_KIND_VOLUME) {
        fade = dc_slab_share(f, l.z, (float2)(lu.z, lv.z), -0.5f, 0.5f);
        if (!texel_edges)
            fade *= dc_slab_share(f, l.x, (float2)(lu.x, lv.x), -0.5f, 0.5f) *
                    dc_slab_share(f, l.y, (float2)(lu.y, lv.y), -0.5f, 0.5f);
        if (!(fade > 0.0f)) return lk;
        if (d->axis_fade > 0.0f) fade *= clamp((0.5f - fabs(l.z)) / (0.5f * d->axis_fade), 0.0f, 1.0f);
        lk.facing = vload3(0, d->facing_axis);
    } else if (d->kind == DC_KIND_FRUSTUM) {
        const float dist = -l.z;
        if (!(dist > 0.0f)) return lk;
        fade = dc_slab_share(f, dist, (float2)(-lu.z, -lv.z), d->near_plane, d->far_plane);
        if (!(fade > 0.0f)) return lk;
        if (d->distance_fade[1] > 0.0f) fade *= dc_ramp_down(dist, d->distance_fade[0], d->distance_fade[1]);
        lk.facing = normalize(dc_decal_origin(d) - p);
    } else { /* DC_KIND_CUBE: no edge, its falloff reaches 0 at the sphere */
        const float r = length(l);
        if (!(r <= 0.5f) || !(r > 0.0f)) return lk;
        fade = clamp(1.0f - r / 0.5f, 0.0f, 1.0f);
        lk.facing = normalize(dc_decal_origin(d) - p);
        lk.face = dc_cube_face(l);
    }
    if (has_normal && d->angle_fade[1] > 0.0f) fade *= dc_angle_fade(d, n, lk.facing);
    lk.coord = dc_decal_coord(d, l, lk.face);
    lk.coord_dx = dc_decal_coord(d, l + lu, lk.face);
    lk.coord_dy = dc_decal_coord(d, l + lv, lk.face);
    if (d->kind == DC_KIND_FRUSTUM && !texel_edges) {
        const float2 su = lk.coord_dx.xy - lk.coord.xy, sv = lk.coord_dy.xy - lk.coord.xy;
        fade *= dc_slab_share(f, lk.coord.x, (float2)(su.x, sv.x), 0.0f, 1.0f) *
                dc_slab_share(f, lk.coord.y, (float2)(su.y, sv.y), 0.0f, 1.0f);
    }
    lk.fade = fade;
    return lk;
}

/* One texture of the set for an integrated lookup: texel by texel where texels carry the edges and
 * on nearest cube faces, else one read over the filter's equivalent box (a stratum as the taps read
 * it). */
DC_INLINE float4 dc_integrated_texel(__constant const DcFrame* f, __global const DcDecal* d, DcLookup lk,
                                     __global const DcTexture* textures, __global const float4* texels, int index,
                                     const int variant) {
    const bool flat = (variant & DC_VARIANT_FLAT) != 0;
    const bool cube_face = !flat && d->kind == DC_KIND_CUBE && d->filter == DC_FILTER_NEAREST;
    if (dc_texel_edges(d) || cube_face) /* a cube face's texels, from the face of the centre */
        return dc_integrate_slice(f, texels, textures, index, lk.coord.xy, lk.coord_dx.xy - lk.coord.xy,
                                  lk.coord_dy.xy - lk.coord.xy, cube_face ? lk.face : 0);
    lk.coord_dx = lk.coord + (lk.coord_dx - lk.coord) * f->filter_box;
    lk.coord_dy = lk.coord + (lk.coord_dy - lk.coord) * f->filter_box;
    return dc_lookup_texel(d, lk, textures, texels, index, variant);
}

#endif
