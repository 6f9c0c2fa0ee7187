/* The UV-space bake of a texture-space decal (docs/texture-space.md "Bake mode"): one work-item per
 * texel finds the rest-mesh triangle that covers it (conservatively: any triangle touching the
 * texel's square), takes the rest point at the texel centre by that triangle's barycentrics (extended
 * past its edge where the centre lies outside), and evaluates the decal there as exact mode does at
 * a pixel's rest point. Texels that no triangle touches but lie within `dilation` texels of an
 * island get the rest point of the face across the island's border (the apron: the neighbouring
 * face across a UV seam unfolded into this island's UV chart, or the border face mirrored where the
 * mesh ends). Mesh data as in DcRestBinding: 3 float4 per vertex, int4 triangles, grids of cells. */
#include "decal_kinds.h"
#include "materials.h"
#include "shared_types.h"

/* A shading program (ComputeDevice::shadingProgram) holds its dc_shade alone. */
#ifndef DC_SHADING_PROGRAM

/* A candidate triangle at a texel: its barycentric weights at the centre and how far the centre is
 * from it (0 inside), then a tie-break (smaller wins). */
typedef struct {
    int triangle;
    float3 w;
    float distance, tie;
} DcBakeHit;

inline float2 dc_vertex_uv(__global const float4* vertices, int v) {
    return (float2)(vertices[3 * v].w, vertices[3 * v + 1].w);
}

inline float dc_segment_distance(float2 p, float2 a, float2 b) {
    const float2 e = b - a;
    const float len2 = dot(e, e);
    const float t = len2 > 0.0f ? clamp(dot(p - a, e) / len2, 0.0f, 1.0f) : 0.0f;
    return length(p - (a + t * e));
}

/* Whether the UV triangle (a, b, c) meets the square centred on p with half-size h (separating
 * axes: the square's two, the triangle's three edge normals). */
inline bool dc_triangle_meets_square(float2 a, float2 b, float2 c, float2 p, float2 h) {
    const float2 lo = fmin(a, fmin(b, c)), hi = fmax(a, fmax(b, c));
    if (lo.x > p.x + h.x || hi.x < p.x - h.x || lo.y > p.y + h.y || hi.y < p.y - h.y) return false;
    const float2 v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
        const float2 s = v[k], e = v[(k + 1) % 3] - s, o = v[(k + 2) % 3] - s;
        float2 n = (float2)(-e.y, e.x);
        if (dot(n, o) < 0.0f) n = -n; /* towards the inside */
        if (dot(n, p - s) + fabs(n.x) * h.x + fabs(n.y) * h.y < 0.0f) return false;
    }
    return true;
}

/* Scans the cells of grid g within `reach` of p for triangles that beat *best. `touch`: only
 * triangles meeting the texel square (half-size h). `apron`: the grid holds apron triangles, whose
 * edge 0-1 is the island border; they count while that edge is within `reach`. */
inline void dc_bake_scan(__global const DcRestBinding* g, __global const float4* vertices, __global const int4* triangles,
                         __global const int* cells, __global const int* cell_triangles, float2 p, float2 h,
                         float2 reach, int touch, int apron, DcBakeHit* best) {
    const float2 origin = vload2(0, g->uv_origin), scale = vload2(0, g->cells_per_uv);
    const float2 lo = (p - reach - origin) * scale, hi = (p + reach - origin) * scale;
    if (hi.x < 0.0f || hi.y < 0.0f || lo.x > (float)g->cells_x || lo.y > (float)g->cells_y) return;
    const int x0 = clamp((int)floor(lo.x), 0, g->cells_x - 1), x1 = clamp((int)floor(hi.x), 0, g->cells_x - 1);
    const int y0 = clamp((int)floor(lo.y), 0, g->cells_y - 1), y1 = clamp((int)floor(hi.y), 0, g->cells_y - 1);
    const float limit = fmax(reach.x, reach.y);
    for (int cy = y0; cy <= y1; ++cy)
        for (int cx = x0; cx <= x1; ++cx) {
            const int c = g->first_cell + cy * g->cells_x + cx;
            for (int k = cells[c]; k < cells[c + 1]; ++k) {
                const int t = cell_triangles[k];
                const int4 tri = triangles[t];
                const float2 a = dc_vertex_uv(vertices, tri.x), b = dc_vertex_uv(vertices, tri.y),
                             cc = dc_vertex_uv(vertices, tri.z);
                const float2 e0 = b - a, e1 = cc - a, dp = p - a;
                const float det = e0.x * e1.y - e0.y * e1.x;
                if (!(fabs(det) > 0.0f)) continue;
                if (touch && !dc_triangle_meets_square(a, b, cc, p, h)) continue;
                const float wb = (dp.x * e1.y - dp.y * e1.x) / det, wc = (e0.x * dp.y - e0.y * dp.x) / det;
                const float3 w = (float3)(1.0f - wb - wc, wb, wc);
                const float inside = fmin(w.x, fmin(w.y, w.z));
                const float distance =
                    inside >= 0.0f ? 0.0f
                                   : fmin(dc_segment_distance(p, a, b),
                                          fmin(dc_segment_distance(p, b, cc), dc_segment_distance(p, cc, a)));
                const float border = apron ? dc_segment_distance(p, a, b) : distance;
                if (!touch && border > limit) continue;
                const float tie = apron ? border : -inside;
                if (distance < best->distance || (distance == best->distance && tie < best->tie)) {
                    best->triangle = t;
                    best->w = w;
                    best->distance = distance;
                    best->tie = tie;
                }
            }
        }
}

/* Barycentric weights of p in triangle t's UV (extended past its edges). */
inline float3 dc_bake_weights(__global const float4* vertices, int4 tri, float2 p) {
    const float2 a = dc_vertex_uv(vertices, tri.x);
    const float2 e0 = dc_vertex_uv(vertices, tri.y) - a, e1 = dc_vertex_uv(vertices, tri.z) - a, dp = p - a;
    const float det = e0.x * e1.y - e0.y * e1.x;
    const float wb = (dp.x * e1.y - dp.y * e1.x) / det, wc = (e0.x * dp.y - e0.y * dp.x) / det;
    return (float3)(1.0f - wb - wc, wb, wc);
}

inline float3 dc_bake_interpolate(__global const float4* vertices, int4 tri, float3 w, int slot) {
    return vertices[3 * tri.x + slot].xyz * w.x + vertices[3 * tri.y + slot].xyz * w.y +
           vertices[3 * tri.z + slot].xyz * w.z;
}

/* Premultiplied value v at coverage c, or nothing. */
inline float4 dc_bake_texel(bool has, float3 v, float c) { return has && c > 0.0f ? (float4)(v * c, c) : (float4)(0.0f); }

/* grids[0]: the rest mesh, grids[1]: its apron, both in the same vertex and triangle buffers.
 * Writes per texel (row 0 at v = 1) the decal's premultiplied albedo (its alpha the coverage times
 * the fades), ORM (ao, roughness, metallic) and emission at the same coverage; 0 where the decal
 * does not reach or no face is near. */
__kernel void dc_bake_layer(__constant const DcBakeLayer* layer, __global const DcDecal* d,
                            __global const DcTexture* textures, __global const float4* texels,
                            __global const DcRestBinding* grids, __global const float4* vertices,
                            __global const int4* triangles, __global const int* cells,
                            __global const int* cell_triangles, __global float4* albedo_out, __global float4* orm_out,
                            __global float4* emission_out) {
    const int i = get_global_id(0), j = get_global_id(1);
    if (i >= layer->width || j >= layer->height) return;
    const size_t out = (size_t)j * layer->width + i;
    albedo_out[out] = orm_out[out] = emission_out[out] = (float4)(0.0f);
    const float2 texel = (float2)(1.0f / layer->width, 1.0f / layer->height);
    const float2 p = (float2)((i + 0.5f) * texel.x, 1.0f - (j + 0.5f) * texel.y), h = 0.5f * texel;
    DcBakeHit best;
    best.triangle = -1;
    best.distance = best.tie = MAXFLOAT;
    dc_bake_scan(&grids[0], vertices, triangles, cells, cell_triangles, p, h, h, 1, 0, &best);
    if (best.triangle < 0 && layer->dilation > 0) {
        const float2 reach = (float)layer->dilation * texel;
        dc_bake_scan(&grids[1], vertices, triangles, cells, cell_triangles, p, h, reach, 0, 1, &best);
        dc_bake_scan(&grids[0], vertices, triangles, cells, cell_triangles, p, h, reach, 0, 0, &best);
    }
    if (best.triangle < 0) return;
    const int4 tri = triangles[best.triangle];
    const float3 rest = dc_bake_interpolate(vertices, tri, best.w, 0);
    const float3 normal = normalize(dc_bake_interpolate(vertices, tri, best.w, 1));
    /* the footprint for mip-filtered decals: the rest points one texel right and one texel down */
    const float3 rest_dx = dc_bake_interpolate(vertices, tri, dc_bake_weights(vertices, tri, p + (float2)(texel.x, 0.0f)), 0);
    const float3 rest_dy = dc_bake_interpolate(vertices, tri, dc_bake_weights(vertices, tri, p - (float2)(0.0f, texel.y)), 0);
    const DcLookup lk = dc_decal_lookup(d, rest, normal, 1, rest_dx, rest_dy, 1);
    if (!(lk.fade > 0.0f)) return;
    float4 albedo = (float4)(0.0f), nmap = (float4)(0.0f), orm = (float4)(0.0f), emission = (float4)(0.0f);
    if (d->texture >= 0) albedo = dc_lookup_texel(d, lk, textures, texels, d->texture, 0);
    if (d->normal_texture >= 0) nmap = dc_lookup_texel(d, lk, textures, texels, d->normal_texture, 0);
    if (d->orm_texture >= 0) orm = dc_lookup_texel(d, lk, textures, texels, d->orm_texture, 0);
    if (d->emission_texture >= 0) emission = dc_lookup_texel(d, lk, textures, texels, d->emission_texture, 0);
    const float c = clamp(dc_set_coverage(d, albedo, nmap, orm, emission) * lk.fade, 0.0f, 1.0f);
    if (!(c > 0.0f)) return;
    float3 v = (float3)(0.0f);
    const bool has_albedo = dc_value3(d, DC_TARGET_ALBEDO, d->albedo_value, d->texture, albedo, &v);
    albedo_out[out] = has_albedo ? (float4)(v * c, c) : (float4)(0.0f, 0.0f, 0.0f, c); /* coverage always */
    /* ORM per channel: the decal's constant where it has one, else the ORM map's. Where the decal has
     * an ORM map and it is transparent, exact mode leaves the map's channels alone: the texel stays
     * empty and the baked decal applies its constants itself (bakedDecal keeps them). */
    float3 straight_orm = (float3)(0.0f);
    const bool has_orm_texture = d->orm_texture >= 0 && dc_straight(orm, &straight_orm);
    const float3 orm_value = (float3)((d->value_mask & (1 << DC_TARGET_AO)) ? d->ao_value : straight_orm.x,
                                      (d->value_mask & (1 << DC_TARGET_ROUGHNESS)) ? d->roughness_value : straight_orm.y,
                                      (d->value_mask & (1 << DC_TARGET_METALLIC)) ? d->metallic_value : straight_orm.z);
    const int orm_constants = (1 << DC_TARGET_AO) | (1 << DC_TARGET_ROUGHNESS) | (1 << DC_TARGET_METALLIC);
    const bool has_orm = d->orm_texture >= 0 ? has_orm_texture : (d->value_mask & orm_constants) != 0;
    orm_out[out] = dc_bake_texel(has_orm, orm_value, c);
    const bool has_emission = dc_value3(d, DC_TARGET_EMISSION, d->emission_value, d->emission_texture, emission, &v);
    emission_out[out] = dc_bake_texel(has_emission, v, c);
}

#endif /* DC_SHADING_PROGRAM */
