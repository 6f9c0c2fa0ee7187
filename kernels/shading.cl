/* Shading: per pixel, the camera-space point, then the tile's decals in order, each blended into
 * the material (DESIGN.md section 3). Background pixels are copied through unchanged.
 * The material travels in three float4 planes: (albedo, roughness), (world normal, metallic),
 * (emission, ao); DcFrame::attributes says which of their parts the frame has. */
#include "beauty.h"
#include "decal_kinds.h"
#include "frame_reads.h"
#include "materials.h"
#include "matrix.h"
#include "occlusion.h"
#include "pixel_filter.h"
#include "reconstruct.h"
#include "rest_pose.h"
#include "shared_types.h"
#include "texture_sample.h"

/* A build that names neither the point program nor a shading program's variant and paths (the
 * build-time checks) compiles every path. */
#if !defined(DC_POINT_SHADING_ONLY) && !defined(DC_SHADE_VARIANT)
#define DC_SHADE_VARIANT 0
#define DC_PATH_TAPS 1
#define DC_PATH_FAST 1
#define DC_PATH_REST 1
#endif

/* The inverse for directions: the transpose of the (rotation) part of world_to_camera. */
inline float3 dc_camera_to_world_vector(__constant const DcFrame* f, float3 v) {
    const __constant float* m = f->world_to_camera;
    return normalize((float3)(m[0] * v.x + m[4] * v.y + m[8] * v.z, m[1] * v.x + m[5] * v.y + m[9] * v.z,
                              m[2] * v.x + m[6] * v.y + m[10] * v.z));
}

inline DcTaps dc_point_taps(void) {
    DcTaps t;
    t.mode = DC_TAPS_POINT;
    return t;
}

/* Decal d at the filter tap pt on `plane`, whose stratum spans the decal-local vectors su, sv,
 * blended into `out` where it reaches the tap. Sets *touched when it does. */
DC_INLINE DcSurface dc_tap_decal(__constant const DcFrame* frame, __global const DcDecal* d, const DcTapPlane* plane,
                                 float3 pt, float3 su, float3 sv, int has_normal, float weight,
                                 __global const DcTexture* textures, __global const float4* texels,
                                 __global const uint* occlusion_maps, DcSurface out, const int variant,
                                 int* touched) {
    const bool albedo_only = (variant & DC_VARIANT_ALBEDO_ONLY) != 0;
    const DcLookup lk = dc_decal_lookup_at(d, pt, plane->n, has_normal, pt, pt, 1, 1, su, sv);
    if (!(lk.fade > 0.0f)) return out;
    if (!albedo_only && d->occlusion_map >= 0 && !dc_blast_reaches(d, occlusion_maps, pt, plane->n)) return out;
    *touched = 1;
    return dc_apply_decal(frame, d, lk, textures, texels, weight, plane->n, out, variant);
}

/* The decal's opacity times its mask's weight at the pixel. */
inline float dc_decal_weight(__constant const DcFrame* frame, __global const DcDecal* d,
                             __global const float* mask_weights, int x, int y) {
    float weight = d->opacity;
    if (d->mask >= 0) weight *= mask_weights[(size_t)d->mask * frame->width * frame->height + y * frame->width + x];
    return weight;
}

/* Decal d integrated over the pixel filter on the pixel's tangent plane in closed form
 * (filter_integral.h, docs/pixel-filter.md "Integrated evaluation"): one lookup whose edges and
 * texels take the filter's shares, blended at that coverage. Sets *applied when it reaches. */
DC_INLINE DcSurface dc_integrated_decal(__constant const DcFrame* frame, __global const DcDecal* d,
                                        const DcTapPlane* plane, int has_normal, int x, int y,
                                        __global const float* mask_weights, __global const uint* occlusion_maps,
                                        __global const DcTexture* textures, __global const float4* texels,
                                        DcSurface s, const int variant, int* applied) {
    const bool albedo_only = (variant & DC_VARIANT_ALBEDO_ONLY) != 0;
    const float3 l = dc_affine_global(d->camera_to_local, plane->p);
    if (!dc_filter_may_reach_at(d, l, plane->reach)) return s;
    const DcLookup lk =
        dc_decal_lookup_integrated(frame, d, l, dc_camera_to_local_vector(d, plane->du),
                                   dc_camera_to_local_vector(d, plane->dv), plane->p, plane->n, has_normal);
    if (!(lk.fade > 0.0f)) return s;
    if (!albedo_only && d->occlusion_map >= 0 && !dc_blast_reaches(d, occlusion_maps, plane->p, plane->n)) return s;
    *applied = 1;
    return dc_apply_decal(frame, d, lk, textures, texels, dc_decal_weight(frame, d, mask_weights, x, y), plane->n, s,
                          variant);
}

/* Entries of a tile's list whose reach is kept in a bit mask; later ones are tested per tap. */
#define DC_STACK_MASK_ENTRIES 64

/* Which of the list's first DC_STACK_MASK_ENTRIES entries from `begin` may reach a tap on `plane`:
 * the footprint's bounding sphere against each decal once per pixel, not once per tap. */
inline ulong dc_reach_mask(__global const DcDecal* decals, __global const int* tile_decals, int binned, int begin,
                           int end, const DcTapPlane* plane) {
    ulong reach = 0;
    for (int k = begin; k < min(end, begin + DC_STACK_MASK_ENTRIES); ++k)
        if (dc_filter_may_reach(&decals[binned ? tile_decals[k] : k], plane)) reach |= (ulong)1 << (k - begin);
    return reach;
}

/* The list's decals [begin, end) that reach the tap at pt on `plane`, blended in list order into
 * `out` (entries in the mask `reach` as dc_reach_mask gives it; later ones tested here). Sets
 * *touched when one did. */
DC_INLINE DcSurface dc_stack_decals(__constant const DcFrame* frame, __global const DcDecal* decals,
                                    __global const int* tile_decals, int binned, int begin, int end, ulong reach,
                                    const DcTapPlane* plane, float3 pt, int has_normal, int x, int y,
                                    __global const float* mask_weights, __global const DcTexture* textures,
                                    __global const float4* texels, __global const uint* occlusion_maps,
                                    DcSurface out, const int variant, int* touched) {
    for (int k = begin; k < end; ++k) {
        __global const DcDecal* d = &decals[binned ? tile_decals[k] : k];
        if (k - begin < DC_STACK_MASK_ENTRIES ? ((reach >> (k - begin)) & 1) == 0 : !dc_filter_may_reach(d, plane))
            continue;
        out = dc_tap_decal(frame, d, plane, pt, dc_camera_to_local_vector(d, plane->du) * frame->filter_step,
                           dc_camera_to_local_vector(d, plane->dv) * frame->filter_step, has_normal,
                           dc_decal_weight(frame, d, mask_weights, x, y), textures, texels, occlusion_maps, out,
                           variant, touched);
    }
    return out;
}

/* The tile's decals [begin, end) integrated over the pixel filter's taps on `plane`, stacked per
 * tap (docs/pixel-filter.md step 3): each tap starts from the pixel's material and blends every
 * decal that reaches it in list order, and the pixel takes the taps' weighted mean. Where decal
 * edges cross inside one footprint this is what the renderer's average gives; a decal alone
 * gives the same as one filtered decal at a time. Sets *applied when some tap reached a decal. */
DC_INLINE DcSurface dc_filter_stacked(__constant const DcFrame* frame, __global const DcDecal* decals,
                                      __global const int* tile_decals, int binned, int begin, int end,
                                      const DcTapRays* rays, const DcTapPlane* plane, int has_normal, int x, int y,
                                      __global const float* mask_weights, __global const DcTexture* textures,
                                      __global const float4* texels, __global const uint* occlusion_maps,
                                      DcSurface s, const int variant, int* applied) {
    const ulong reach = dc_reach_mask(decals, tile_decals, binned, begin, end, plane);
    if (reach == 0 && end - begin <= DC_STACK_MASK_ENTRIES) return s;
    DcSurface acc = dc_surface_add_scaled(s, s, -1.0f);
    int touched = 0;
    for (int j = 0; j < frame->filter_taps; ++j)
        for (int i = 0; i < frame->filter_taps; ++i) {
            DcSurface out = s;
            float3 pt;
            if (dc_tap_point(rays, plane, frame->filter_offset[i], frame->filter_offset[j], &pt))
                out = dc_stack_decals(frame, decals, tile_decals, binned, begin, end, reach, plane, pt, has_normal, x,
                                      y, mask_weights, textures, texels, occlusion_maps, out, variant, &touched);
            acc = dc_surface_add_scaled(acc, out, frame->filter_weight[i] * frame->filter_weight[j]);
        }
    if (!touched) return s;
    if (acc.normal_changed && length(acc.normal) > 1e-6f) acc.normal = normalize(acc.normal);
    *applied = 1;
    return acc;
}

/* The material of one side of a split pixel, as DcTaps keeps it. */
inline DcSurface dc_split_material(const DcTaps* taps, int side, DcSurface s) {
    s.albedo = taps->material[side].xyz;
    s.roughness = taps->material[side].w;
    s.metallic = taps->metallic[side];
    s.normal = taps->normal[side];
    return s;
}

/* One surface of a split pixel (docs/pixel-filter.md "Silhouettes"): each tap's share on `plane`
 * (the nearer surface's, or with `far_side` the farther's) starts from the surface's material
 * `base` and blends the list's decals [begin, end) that reach it, in order (`reach`: their mask as
 * dc_reach_mask gives it on this plane). Returns the sum of the taps' results weighted by filter
 * and share, and adds the weights to *total. */
DC_INLINE DcSurface dc_filter_stacked_side(__constant const DcFrame* frame, __global const DcDecal* decals,
                                           __global const int* tile_decals, int binned, int begin, int end,
                                           const DcTaps* taps, const DcTapPlane* plane, const int far_side,
                                           ulong reach, DcSurface base, int has_normal, int x, int y,
                                           __global const float* mask_weights, __global const DcTexture* textures,
                                           __global const float4* texels, __global const uint* occlusion_maps,
                                           const int variant, float* total, int* touched) {
    DcSurface sum = dc_surface_add_scaled(base, base, -1.0f);
    for (int j = 0; j < frame->filter_taps; ++j)
        for (int i = 0; i < frame->filter_taps; ++i) {
            const float u = frame->filter_offset[i], v = frame->filter_offset[j];
            const float near = dc_tap_share(taps, u, v);
            const float share = far_side ? 1.0f - near : near;
            if (!(share > 0.0f)) continue;
            DcSurface out = base;
            float3 pt;
            if (dc_tap_point(&taps->rays, plane, u, v, &pt))
                out = dc_stack_decals(frame, decals, tile_decals, binned, begin, end, reach, plane, pt, has_normal, x,
                                      y, mask_weights, textures, texels, occlusion_maps, out, variant, touched);
            const float w = frame->filter_weight[i] * frame->filter_weight[j] * share;
            sum = dc_surface_add_scaled(sum, out, w);
            *total += w;
        }
    return sum;
}

/* acc plus one side's change, sum - base total (dc_filter_stacked_side), where its taps weigh. */
inline DcSurface dc_add_side_change(DcSurface acc, DcSurface sum, DcSurface base, float total) {
    if (!(total > 0.0f)) return acc;
    return dc_surface_add_scaled(dc_surface_add_scaled(acc, sum, 1.0f), base, -total);
}

/* The split pixel's version of dc_filter_stacked (docs/pixel-filter.md "Silhouettes"): each tap's
 * share on each surface starts from that surface's material and blends every decal reaching it in
 * list order; the pixel keeps its mix and adds each share's change. (The sides are two calls, not a
 * loop over `side`: a plane or material chosen at run time keeps the taps in memory on GPUs, 12 %
 * of the closed form's time on an H100.) */
DC_INLINE DcSurface dc_filter_stacked_split(__constant const DcFrame* frame, __global const DcDecal* decals,
                                            __global const int* tile_decals, int binned, int begin, int end,
                                            const DcTaps* taps, int has_normal, int x, int y,
                                            __global const float* mask_weights, __global const DcTexture* textures,
                                            __global const float4* texels, __global const uint* occlusion_maps,
                                            DcSurface s, const int variant, int* applied) {
    const ulong reach_near = dc_reach_mask(decals, tile_decals, binned, begin, end, &taps->plane);
    const ulong reach_far = dc_reach_mask(decals, tile_decals, binned, begin, end, &taps->other);
    if ((reach_near | reach_far) == 0 && end - begin <= DC_STACK_MASK_ENTRIES) return s;
    const DcSurface base_near = dc_split_material(taps, 0, s), base_far = dc_split_material(taps, 1, s);
    float total_near = 0.0f, total_far = 0.0f;
    int touched = 0;
    const DcSurface sum_near =
        dc_filter_stacked_side(frame, decals, tile_decals, binned, begin, end, taps, &taps->plane, 0, reach_near,
                               base_near, has_normal, x, y, mask_weights, textures, texels, occlusion_maps, variant,
                               &total_near, &touched);
    const DcSurface sum_far =
        dc_filter_stacked_side(frame, decals, tile_decals, binned, begin, end, taps, &taps->other, 1, reach_far,
                               base_far, has_normal, x, y, mask_weights, textures, texels, occlusion_maps, variant,
                               &total_far, &touched);
    if (!touched) return s;
    DcSurface acc = dc_add_side_change(dc_add_side_change(s, sum_near, base_near, total_near), sum_far, base_far,
                                       total_far);
    if (acc.normal_changed && length(acc.normal) > 1e-6f) acc.normal = normalize(acc.normal);
    *applied = 1;
    return acc;
}

/* List entry k's decal at a split pixel, one decal at a time (frames with texture-space decals,
 * whose rest-space taps are placed per decal): each surface's taps blend it into that surface's
 * material; the pixel keeps its mix and adds each surface's change, weighted by its taps. Each
 * surface's material then becomes the mean of its taps' results, for the next decal. */
DC_INLINE DcSurface dc_filter_decal_split(__constant const DcFrame* frame, __global const DcDecal* decals,
                                          __global const int* tile_decals, int binned, int k, DcTaps* taps,
                                          int has_normal, int x, int y, __global const float* mask_weights,
                                          __global const DcTexture* textures, __global const float4* texels,
                                          __global const uint* occlusion_maps, DcSurface s, const int variant,
                                          int* applied) {
    __global const DcDecal* d = &decals[binned ? tile_decals[k] : k];
    const bool reach_near = dc_filter_may_reach(d, &taps->plane), reach_far = dc_filter_may_reach(d, &taps->other);
    if (!reach_near && !reach_far) return s;
    const DcSurface base_near = dc_split_material(taps, 0, s), base_far = dc_split_material(taps, 1, s);
    float total_near = 0.0f, total_far = 0.0f;
    int touched = 0;
    /* each side it may reach: the list of this one entry */
    const DcSurface sum_near =
        reach_near ? dc_filter_stacked_side(frame, decals, tile_decals, binned, k, k + 1, taps, &taps->plane, 0, 1,
                                            base_near, has_normal, x, y, mask_weights, textures, texels,
                                            occlusion_maps, variant, &total_near, &touched)
                   : base_near;
    const DcSurface sum_far =
        reach_far ? dc_filter_stacked_side(frame, decals, tile_decals, binned, k, k + 1, taps, &taps->other, 1, 1,
                                           base_far, has_normal, x, y, mask_weights, textures, texels, occlusion_maps,
                                           variant, &total_far, &touched)
                  : base_far;
    if (!touched) return s;
    DcSurface acc = dc_add_side_change(dc_add_side_change(s, sum_near, base_near, total_near), sum_far, base_far,
                                       total_far);
    if (acc.normal_changed && length(acc.normal) > 1e-6f) acc.normal = normalize(acc.normal);
    for (int side = 0; side < 2; ++side) {
        const float total = side == 0 ? total_near : total_far;
        if (!(total > 0.0f)) continue;
        const DcSurface m = dc_surface_add_scaled(dc_surface_add_scaled(s, s, -1.0f), side == 0 ? sum_near : sum_far,
                                                  1.0f / total);
        taps->material[side] = (float4)(m.albedo, m.roughness);
        taps->metallic[side] = m.metallic;
        if (m.normal_changed && length(m.normal) > 1e-6f) taps->normal[side] = normalize(m.normal);
    }
    *applied = 1;
    return acc;
}

/* A decal's pixel range (binning.cl dc_decal_bounds) as (x0, y0, x1, y1), inclusive. */
inline int4 dc_pixel_range(__global const DcDecalBounds* b) {
    return (int4)(b->pixel_x0, b->pixel_y0, b->pixel_x1, b->pixel_y1);
}

/* Whether pixel (x, y) lies in the range r (dc_pixel_range). */
inline bool dc_range_holds(int4 r, int x, int y) { return x >= r.x && x <= r.z && y >= r.y && y <= r.w; }

/* A tile's list in local memory: its first entries' decal indices and pixel ranges. Every pixel of
 * the tile walks the list in step, and from global memory each step was two dependent loads (the
 * entry, then its decal's range); from here it is one (H100: the point-sampled kernels 3-7 %
 * faster, docs/benchmarks.md). */
#define DC_STAGED_ENTRIES (DC_TILE_SIZE * DC_TILE_SIZE)
typedef struct {
    int index[DC_STAGED_ENTRIES];
    int4 range[DC_STAGED_ENTRIES];
} DcStagedList;

/* The group's work-items copy the list's first entries [begin, end) into `staged` together, one
 * entry each; returns how many. Every work-item of the group must call it (a barrier). */
inline int dc_stage_list(__local DcStagedList* staged, __global const int* tile_decals,
                         __global const DcDecalBounds* decal_bounds, int begin, int end) {
    const int lid = get_local_id(1) * DC_TILE_SIZE + get_local_id(0);
    const int count = min(end - begin, DC_STAGED_ENTRIES);
    if (lid < count) {
        const int index = tile_decals[begin + lid];
        staged->index[lid] = index;
        staged->range[lid] = dc_pixel_range(&decal_bounds[index]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    return count;
}

/* List entry k's decal in *index (the first `staged_count` entries from local memory); false where
 * `pixel_test` holds and the decal's pixel range misses pixel (x, y). */
inline bool dc_list_entry(__local const DcStagedList* staged, int staged_count, __global const int* tile_decals,
                          __global const DcDecalBounds* decal_bounds, int binned, int pixel_test, int begin, int k,
                          int x, int y, int* index) {
    if (k - begin < staged_count) {
        *index = staged->index[k - begin];
        return !pixel_test || dc_range_holds(staged->range[k - begin], x, y);
    }
    *index = binned ? tile_decals[k] : k;
    return !pixel_test || dc_range_holds(dc_pixel_range(&decal_bounds[*index]), x, y);
}

/* Decal d point-sampled at the pixel centre p. Sets *applied when the decal reaches p. */
DC_INLINE DcSurface dc_point_decal(__constant const DcFrame* frame, __global const DcDecal* d, float3 p,
                                   float3 normal, int has_normal, float3 p_dx, float3 p_dy, int footprint, int x,
                                   int y, __global const float* mask_weights, __global const uint* occlusion_maps,
                                   __global const DcTexture* textures, __global const float4* texels, DcSurface s,
                                   const int variant, int* applied) {
    const bool albedo_only = (variant & DC_VARIANT_ALBEDO_ONLY) != 0;
    const DcLookup lk = dc_decal_lookup(d, p, normal, has_normal, p_dx, p_dy, footprint);
    if (!(lk.fade > 0.0f)) return s;
    /* blast occlusion: a surface nearer the origin hides this one from the blast */
    if (!albedo_only && d->occlusion_map >= 0 && !dc_blast_reaches(d, occlusion_maps, p, normal)) return s;
    *applied = 1;
    return dc_apply_decal(frame, d, lk, textures, texels, dc_decal_weight(frame, d, mask_weights, x, y), normal, s,
                          variant);
}

/* A pixel whose list [begin, end) is not empty (its tile's, binned; every decal, unbinned), with
 * its depth sample (and in the point program its first surface plane's value) as loaded:
 * composites the list into the surface planes and returns the beauty's change (dc_beauty_change; 0
 * where nothing changed or without a beauty). */
inline float3 dc_shade_listed_pixel(__constant const DcFrame* frame, __global const float* depth_plane,
                                    __global const float4* position_plane, __global float4* surface0,
                                    __global float4* surface1, __global float4* surface2,
                                    __global const float4* original0, __global const float4* original1,
                                    __global const float* clean_depths,
                                    __global const DcDecal* decals, __global const DcTexture* textures,
                                    __global const float4* texels, __global const int* tile_decals,
                                    __global const DcDecalBounds* decal_bounds, int binned, int begin, int end,
                                    __local const DcStagedList* staged, int staged_count,
                                    __global const float* mask_weights, __global const uint* occlusion_maps,
                                    __global float* light, __global const float4* rest_points,
                                    __global const float4* rest_frames, const int variant, int x, int y,
                                    float depth, float4 in0_loaded) {
    const size_t i = (size_t)y * frame->width + x;
    const bool has_group1 = dc_has_group1(frame), has_group2 = dc_has_group2(frame);
    /* Binning leaves each decal's pixel range (with the filter taps' reach): a decal whose range
     * misses the pixel does not reach it, and the point-sampled and closed-form loops below skip it
     * before any transform (the taps test each decal's reach on the footprint's plane instead).
     * Positions from a position pass need not project onto their pixel, and texture-space decals
     * follow the rest pose: those frames skip the test. (Narrowing the list to the entries whose
     * ranges hold the pixel, returning early where none does, cost more on an H100 than it saved:
     * 4-12 % of the point-sampled kernels, 11-14 % of the filtered ones; docs/benchmarks.md, stop 41.) */
    const bool pixel_test = binned && frame->depth_convention != DC_DEPTH_POSITION && !frame->rest_decals;
    float3 p;
    if (!dc_reconstruct_from(frame, depth, position_plane, x, y, &p)) return (float3)(0.0f);
#ifdef DC_POINT_SHADING_ONLY
    const float4 in0 = in0_loaded;
#else
    (void)in0_loaded; /* (loaded early, the filter's kernels ran 1-2 % slower on an H100) */
    const float4 in0 = surface0[i];
#endif
    const float4 in1 = has_group1 ? surface1[i] : (float4)(0.0f);
    const float4 in2 = has_group2 ? surface2[i] : (float4)(0.0f);
    /* the light terms' loads before the decals, so that their latency hides behind the decal loop */
    const size_t pixels = (size_t)frame->width * frame->height;
    const float3 early_l0 = frame->beauty && frame->light_terms > 0 ? vload3(i, light) : (float3)(0.0f);
    const float3 early_l1 = frame->beauty && frame->light_terms > 1 ? vload3(pixels + i, light) : (float3)(0.0f);
    {
        float3 normal = (float3)(0.0f);
        if (frame->reconstruct_normals)
            normal = dc_normal_from_depth(frame, depth_plane, position_plane, x, y, p);
        else if (frame->has_normal)
            normal = normalize(dc_world_to_camera_vector(frame, in1.xyz));
        const int has_normal = frame->has_normal || frame->reconstruct_normals;
        float3 p_dx = p, p_dy = p;
        const int footprint =
            has_normal && frame->needs_footprint && dc_footprint(frame, x, y, p, normal, &p_dx, &p_dy);
        DcSurface s;
        s.albedo = in0.xyz;
        s.roughness = in0.w;
        s.normal = normal;
        s.metallic = in1.w;
        s.emission = in2.xyz;
        s.ao = in2.w;
        s.normal_changed = 0;
        int applied = 0;
#ifdef DC_POINT_SHADING_ONLY
        /* The point program (device.cpp) holds the point kernels alone: none of the filter's or the
         * rest pose's code reaches its compiler, whose cold build that code slowed down (their
         * planes stay arguments, so both programs' kernels take the same ones). */
        (void)original0, (void)original1, (void)clean_depths, (void)rest_points, (void)rest_frames;
        if (1) {
#else
        /* A shading program (device.cpp) holds the paths its build names (DC_PATH_x): each inlines
         * a whole decal evaluation, and NVIDIA's compiler took minutes over all of them at once. */
#if !DC_PATH_REST
        (void)rest_points, (void)rest_frames;
#endif
        DcTaps taps = frame->filter_taps > 0 && has_normal
                                ? dc_taps(frame, depth_plane, position_plane, original0, original1, clean_depths,
                                          frame->has_normal, x, y, p, normal, in1.xyz)
                                : dc_point_taps();
        /* (a program of the rest pose's loop alone has no other branch: texture-space frames take it) */
        if (DC_PATH_TAPS + DC_PATH_FAST > 0 && taps.mode == DC_TAPS_POINT && !frame->rest_decals) {
#endif
            /* The common case in a loop of its own: without the branches to the pixel filter and the
             * rest pose in its body the compiler keeps it lean (PoCL: 1.4x, docs/benchmarks.md). */
            /* outside a decal's pixel range, no transform (pixel_test above) */
            for (int k = begin; k < end; ++k) {
                int index;
                if (!dc_list_entry(staged, staged_count, tile_decals, decal_bounds, binned, pixel_test, begin, k, x, y,
                                   &index))
                    continue;
                s = dc_point_decal(frame, &decals[index], p, normal, has_normal, p_dx, p_dy, footprint, x, y,
                                   mask_weights, occlusion_maps, textures, texels, s, variant, &applied);
            }
#ifndef DC_POINT_SHADING_ONLY
#if DC_PATH_TAPS
        } else if (taps.mode == DC_TAPS_PLANE && !frame->rest_decals && !frame->filter_fast) {
            s = dc_filter_stacked(frame, decals, tile_decals, binned, begin, end, &taps.rays, &taps.plane, has_normal,
                                  x, y, mask_weights, textures, texels, occlusion_maps, s, variant, &applied);
#endif
#if DC_PATH_FAST
        } else if (taps.mode == DC_TAPS_PLANE && !frame->rest_decals && frame->filter_fast) {
            for (int k = begin; k < end; ++k) {
                int index;
                if (!dc_list_entry(staged, staged_count, tile_decals, decal_bounds, binned, pixel_test, begin, k, x, y,
                                   &index))
                    continue;
                s = dc_integrated_decal(frame, &decals[index], &taps.plane, has_normal, x, y, mask_weights,
                                        occlusion_maps, textures, texels, s, variant, &applied);
            }
#endif
#if DC_PATH_TAPS || DC_PATH_FAST
        } else if (taps.mode == DC_TAPS_SPLIT && !frame->rest_decals) {
            s = dc_filter_stacked_split(frame, decals, tile_decals, binned, begin, end, &taps, has_normal, x, y,
                                        mask_weights, textures, texels, occlusion_maps, s, variant, &applied);
#endif
#if DC_PATH_REST
        } else if (frame->rest_decals) {
            for (int k = begin; k < end; ++k) {
                __global const DcDecal* d = &decals[binned ? tile_decals[k] : k];
                if (d->rest_binding >= 0) /* texture-space: at its rest point(s) (rest_pose.h) */
                    s = dc_apply_rest_decal(frame, d, rest_points, rest_frames, x, y, normal, has_normal,
                                            taps.mode != DC_TAPS_POINT, dc_decal_weight(frame, d, mask_weights, x, y),
                                            textures, texels, s, variant, &applied);
                else if (taps.mode == DC_TAPS_SPLIT)
                    s = dc_filter_decal_split(frame, decals, tile_decals, binned, k, &taps, has_normal, x, y,
                                              mask_weights, textures, texels, occlusion_maps, s, variant, &applied);
                else if (taps.mode != DC_TAPS_POINT) /* this decal alone over the taps */
                    s = dc_filter_stacked(frame, decals, tile_decals, binned, k, k + 1, &taps.rays, &taps.plane,
                                          has_normal, x, y, mask_weights, textures, texels, occlusion_maps, s, variant,
                                          &applied);
                else
                    s = dc_point_decal(frame, d, p, normal, has_normal, p_dx, p_dy, footprint, x, y, mask_weights,
                                       occlusion_maps, textures, texels, s, variant, &applied);
            }
#endif
#endif
        }
        if (!applied) return (float3)(0.0f);
        const float3 world_normal = s.normal_changed ? dc_camera_to_world_vector(frame, s.normal) : in1.xyz;
        surface0[i] = (float4)(s.albedo, s.roughness);
        if (has_group1) surface1[i] = (float4)(world_normal, s.metallic);
        if (has_group2) surface2[i] = (float4)(s.emission, s.ao);
        if (frame->beauty) {
            const float relight = frame->relight && s.normal_changed
                                      ? dc_relight_ratio(frame, normalize(in1.xyz), world_normal)
                                      : 1.0f;
            /* mixed pixels of filtered frames, for divided light without relighting (beauty.h) */
#ifdef DC_POINT_SHADING_ONLY
            const uint mixed_surfaces = 0u;
#else
            const uint mixed_surfaces = frame->filter_taps > 0 && frame->light_divided && !frame->relight
                                            ? dc_mixed_surfaces(frame, depth_plane, position_plane, x, y, -p.z, in1.xyz)
                                            : 0u;
#endif
            return dc_beauty_change(frame, i, pixels, in0.xyz, s.albedo, s.emission - in2.xyz, relight,
                                    mixed_surfaces, light, early_l0, early_l1);
        }
    }
    return (float3)(0.0f);
}

#if DC_TILE_SIZE != 16
#error "dc_shade_pixel maps a 16 x 16 work-group's work-items to pixels"
#endif

#ifdef DC_CPU_DEVICE
/* A CPU device runs a tile's work-items one after another, row by row, each row a new stream that
 * the hardware prefetcher does not follow: every first read of a plane's cache line waited in
 * full. The tile's first DC_TILE_SIZE work-items each read one of its rows ahead (dc_touch), so
 * the misses overlap (PoCL: `:fast` 3 % faster, docs/benchmarks.md stop 53). */
inline void dc_touch_tile_row(__constant const DcFrame* frame, __global const float* depth_plane,
                              __global const float4* surface0, __global const float4* surface1, int row_in_tile) {
    const int y = min((int)get_group_id(1) * DC_TILE_SIZE + row_in_tile, frame->height - 1);
    const int x = min((int)get_group_id(0) * DC_TILE_SIZE, frame->width - 1);
    const size_t first = (size_t)y * frame->width + x;
    const int last = min(DC_TILE_SIZE, frame->width - x) - 1;
    const bool has_group1 = dc_has_group1(frame);
    for (int k = 0; k <= last; k += 4) { /* a 64-byte line holds 4 pixels of a float4 plane */
        dc_touch((const __global float*)(surface0 + first + k));
        if (has_group1) dc_touch((const __global float*)(surface1 + first + k));
    }
    if (frame->has_depth) {
        dc_touch(depth_plane + first);
        dc_touch(depth_plane + first + last);
    }
}
#endif

/* One pixel. `variant` (DC_VARIANT_x) is a literal in each kernel below, so the lean kernels carry
 * none of the code they exclude (fewer registers, faster loops: docs/benchmarks.md). */
inline void dc_shade_pixel(__constant const DcFrame* frame, __global const float* depth_plane,
                           __global const float4* position_plane, __global float4* surface0,
                           __global float4* surface1, __global float4* surface2,
                           __global const float4* original0, __global const float4* original1,
                           __global const float* clean_depths,
                           __global const DcDecal* decals, __global const DcTexture* textures,
                           __global const float4* texels, __global const int* tile_offsets,
                           __global const int* tile_decals, __global const DcDecalBounds* decal_bounds, int binned,
                           int list_capacity,
                           __global const float* mask_weights,
                           __global const uint* occlusion_maps, __global float* beauty,
                           __global float* light, __global const float4* rest_points,
                           __global const float4* rest_frames, __local DcStagedList* staged, const int variant) {
    /* Work-groups are tiles of 16 x 16 pixels (compositor.cpp). Each 32 work-items (a warp on NVIDIA)
     * shade 8 x 4 of its pixels rather than two rows of 16, so fewer decal edges divide a warp (H100:
     * the kernels 1-3 % faster, docs/benchmarks.md). A CPU runs the work-items one by one: there
     * they go row by row, each row a run of 256 bytes of a float4 plane (PoCL: 2-3 % faster). */
    const int lid = get_local_id(1) * DC_TILE_SIZE + get_local_id(0);
#ifdef DC_CPU_DEVICE
    const int x = get_group_id(0) * DC_TILE_SIZE + (lid & (DC_TILE_SIZE - 1));
    const int y = get_group_id(1) * DC_TILE_SIZE + lid / DC_TILE_SIZE;
#else
    const int x = get_group_id(0) * DC_TILE_SIZE + ((lid >> 5) & 1) * 8 + (lid & 7);
    const int y = get_group_id(1) * DC_TILE_SIZE + (lid >> 6) * 4 + ((lid >> 3) & 3);
#endif
    /* The surface planes are changed in place: pixels no decal reaches (background among them)
     * are not written, so they keep their samples bit for bit. (The beauty's change is
     * written, 0 there, at every pixel of a listed tile.) */
    int begin = 0, end = frame->decal_count;
    if (binned) {
        const int tile = get_group_id(1) * frame->tiles_x + get_group_id(0);
        begin = tile_offsets[tile];
        end = min(tile_offsets[tile + 1], list_capacity); /* an overflowed list: the frame runs again */
    }
    /* the tile's list before the pixel's point: tiles no decal reaches read nothing but it (the
     * whole group returns, before the list's staging and its barrier) */
    if (begin >= end) return;
#ifdef DC_CPU_DEVICE
    if (lid < DC_TILE_SIZE) dc_touch_tile_row(frame, depth_plane, surface0, surface1, lid);
#endif
    const bool in_frame = x < frame->width && y < frame->height;
    const size_t i = in_frame ? (size_t)y * frame->width + x : 0;
#ifdef DC_POINT_SHADING_ONLY
    /* The pixel's depth and first surface plane are loaded before the list is staged, whatever its
     * depth: the loads wait alongside the staging's loads and barrier, not after them (H100: the
     * point kernels 1-2 % faster, docs/benchmarks.md). */
    const float depth = in_frame ? dc_pixel_depth(frame, depth_plane, x, y) : 0.0f;
    const float4 in0 = in_frame ? surface0[i] : (float4)(0.0f);
    const int staged_count = binned ? dc_stage_list(staged, tile_decals, decal_bounds, begin, end) : 0;
    if (!in_frame) return;
#else
    const int staged_count = 0;
    if (!in_frame) return;
    const float depth = dc_pixel_depth(frame, depth_plane, x, y);
    const float4 in0 = (float4)(0.0f); /* read after the point's reconstruction (dc_shade_listed_pixel) */
#endif
    /* Every pixel of a listed tile writes its beauty change, 0 where nothing changed: the host adds
     * the changes of exactly those tiles (beauty_transfer.hpp), and the kernel never reads the beauty.
     * With one light term that no neighbour reads (change_in_light), the change takes the place of
     * the pixel's term, which it loaded before: a CPU then writes lines already in its cache. */
    const float3 change = dc_shade_listed_pixel(frame, depth_plane, position_plane, surface0, surface1, surface2,
                                                original0, original1, clean_depths, decals, textures, texels,
                                                tile_decals, decal_bounds, binned, begin, end, staged, staged_count,
                                                mask_weights, occlusion_maps, light, rest_points, rest_frames, variant,
                                                x, y, depth, in0);
    if (frame->beauty) vstore3(change, i, frame->change_in_light ? light : beauty);
}

#define DC_SHADE_ARGUMENTS                                                                                       \
    __constant const DcFrame *frame, __global const float *depth_plane, __global const float4 *position_plane,  \
        __global float4 *surface0, __global float4 *surface1, __global float4 *surface2,                         \
        __global const float4 *original0, __global const float4 *original1, __global const float *clean_depths,  \
        __global const DcDecal *decals, __global const DcTexture *textures, __global const float4 *texels,       \
        __global const int *tile_offsets, __global const int *tile_decals,                                      \
        __global const DcDecalBounds *decal_bounds, int binned, int list_capacity,                              \
        __global const float *mask_weights, __global const uint *occlusion_maps, __global float *beauty,        \
        __global float *light, __global const float4 *rest_points, __global const float4 *rest_frames
#define DC_SHADE_CALL(VARIANT, STAGED)                                                                      \
    dc_shade_pixel(frame, depth_plane, position_plane, surface0, surface1, surface2, original0, original1,       \
                   clean_depths,                                                                              \
                   decals, textures, texels,                                                                  \
                   tile_offsets, tile_decals, decal_bounds, binned, list_capacity,                            \
                   mask_weights, occlusion_maps, beauty, light, rest_points, rest_frames, STAGED, VARIANT)
/* STAGED: the tile's list in local memory, which OpenCL C 1.2 declares in the kernel's own scope
 * (the point kernels); 0 where the kernel stages none (the shading programs) */

/* The point program (DC_POINT_SHADING_ONLY): every target, kind and blast occlusion, then leaner
 * kernels the host picks when a scene fits, none with the pixel filter's or the rest pose's code,
 * and so none of their registers (docs/benchmarks.md). */
#ifdef DC_POINT_SHADING_ONLY
__kernel void dc_shade_point(DC_SHADE_ARGUMENTS) {
    __local DcStagedList staged;
    DC_SHADE_CALL(DC_VARIANT_POINT, &staged);
}
__kernel void dc_shade_point_albedo(DC_SHADE_ARGUMENTS) {
    __local DcStagedList staged;
    DC_SHADE_CALL(DC_VARIANT_POINT | DC_VARIANT_ALBEDO_ONLY, &staged);
}
__kernel void dc_shade_point_flat(DC_SHADE_ARGUMENTS) {
    __local DcStagedList staged;
    DC_SHADE_CALL(DC_VARIANT_POINT | DC_VARIANT_FLAT, &staged);
}
__kernel void dc_shade_point_albedo_flat(DC_SHADE_ARGUMENTS) {
    __local DcStagedList staged;
    DC_SHADE_CALL(DC_VARIANT_POINT | DC_VARIANT_ALBEDO_ONLY | DC_VARIANT_FLAT, &staged);
}
#else
/* A shading program (ComputeDevice::shadingProgram), for filtered and texture-space frames: one
 * kernel, of the variant (DC_SHADE_VARIANT) and with the paths (DC_PATH_TAPS, DC_PATH_FAST,
 * DC_PATH_REST) its build names. */
__kernel void dc_shade(DC_SHADE_ARGUMENTS) {
    DC_SHADE_CALL(DC_SHADE_VARIANT, 0);
}
#endif

#undef DC_SHADE_ARGUMENTS
#undef DC_SHADE_CALL
