/* Binning: each decal's conservative screen footprint, then per-tile decal lists in two passes
 * (count, then fill at offsets from a prefix sum), so lists keep decal order and never drop one. */
#include "shared_types.h"
#include "matrix.h"
#include "pixel_filter.h"
#include "work_group.h"

/* A shading program (ComputeDevice::shadingProgram) holds its dc_shade alone. */
#ifndef DC_SHADING_PROGRAM

/* Relative and absolute slack on depth ranges, for float rounding in both sides of the test. */
#define DC_DEPTH_SLACK_REL 1e-4f
#define DC_DEPTH_SLACK_ABS 1e-6f
/* pixels of slack for the rounding of a decal's projected corners against its pixels' rays */
#define DC_RANGE_ROUNDING 0.01f

/* w of a camera-space point under the projection: -z for perspective, 1 for orthographic. */
inline float dc_clip_w(__constant const DcFrame* f, float3 p) {
    return dot(vload4(3, f->projection), (float4)(p, 1.0f));
}

inline void dc_extend(__constant const DcFrame* f, float3 p, float4* rect, float2* depth) {
    const float4 c = dc_mul4_constant(f->projection, (float4)(p, 1.0f));
    const float2 ndc = c.xy / c.w;
    const float px = (ndc.x + 1.0f) * 0.5f * (float)f->display_width - (float)f->origin_x;
    const float py = (1.0f - ndc.y) * 0.5f * (float)f->display_height - (float)f->origin_y;
    *rect = (float4)(fmin(rect->x, px), fmin(rect->y, py), fmax(rect->z, px), fmax(rect->w, py));
    *depth = (float2)(fmin(depth->x, -p.z), fmax(depth->y, -p.z));
}

/* The decal's unit box is clipped against the plane w = DC_MIN_VIEW_DEPTH (pixels nearer are
 * never decaled); the remaining corners and edge crossings bound its projection. */
__kernel void dc_decal_bounds(__constant const DcFrame* frame, __global const DcDecal* decals,
                              __global DcDecalBounds* bounds) {
    const int id = get_global_id(0);
    if (id >= frame->decal_count) return;
    __global const float* m = decals[id].local_to_camera;

    float3 corner[8];
    float w[8];
    __global const DcDecal* d = &decals[id];
    if (d->rest_binding >= 0) { /* texture-space: wherever its object is seen; the rest pass decides */
        DcDecalBounds all;
        all.tile_x0 = all.tile_y0 = 0;
        all.tile_x1 = frame->tiles_x - 1;
        all.tile_y1 = frame->tiles_y - 1;
        all.depth_min = -MAXFLOAT;
        all.depth_max = MAXFLOAT;
        all.pixel_x0 = all.pixel_y0 = 0;
        all.pixel_x1 = frame->width - 1;
        all.pixel_y1 = frame->height - 1;
        bounds[id] = all;
        return;
    }
    for (int i = 0; i < 8; ++i) {
        /* corners of the decal's volume in local space, bit 0: x, bit 1: y, bit 2: z / near-far */
        float3 local_point = (float3)((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f);
        if (d->kind == DC_KIND_FRUSTUM) {
            const float dist = (i & 4) ? d->far_plane : d->near_plane;
            const float half_h = dist * d->tan_half_fov_y;
            local_point = (float3)((i & 1) ? half_h * d->aspect : -half_h * d->aspect, (i & 2) ? half_h : -half_h, -dist);
        }
        corner[i] = dc_affine_global(m, local_point);
        w[i] = dc_clip_w(frame, corner[i]) - (frame->orthographic ? 0.0f : DC_MIN_VIEW_DEPTH);
    }
    float4 rect = (float4)(MAXFLOAT, MAXFLOAT, -MAXFLOAT, -MAXFLOAT);
    float2 depth = (float2)(MAXFLOAT, -MAXFLOAT);
    int kept = 0;
    for (int i = 0; i < 8; ++i) {
        if (w[i] >= 0.0f) {
            dc_extend(frame, corner[i], &rect, &depth);
            ++kept;
        }
        for (int axis = 1; axis <= 4; axis <<= 1) {  /* the 12 edges, each once from its low end */
            const int j = i | axis;
            if (j == i) continue;
            if ((w[i] >= 0.0f) != (w[j] >= 0.0f)) {
                const float t = w[i] / (w[i] - w[j]);
                float3 q = mix(corner[i], corner[j], t);
                /* keep the crossing on the visible side despite rounding */
                if (!frame->orthographic) q.z = fmin(q.z, -DC_MIN_VIEW_DEPTH);
                dc_extend(frame, q, &rect, &depth);
            }
        }
    }
    DcDecalBounds b;
    const float big = 1e9f; /* keeps pixel coordinates in int range */
    /* A point-sampled pixel whose point comes from its depth lies on its centre's ray, so the
     * decal reaches it only where the centre (x + 0.5) projects inside rect: the range holds those
     * pixels, with DC_RANGE_ROUNDING for the projections' rounding. Pixel-filter taps reach
     * filter_radius pixels (and half a stratum) further, and a position pass's points need not lie
     * on their pixel's ray: those keep a margin of a pixel more. */
    const float4 r = clamp(rect, -big, big);
    float x0, y0, x1, y1;
    if (frame->filter_taps == 0 && frame->depth_convention != DC_DEPTH_POSITION) {
        x0 = ceil(r.x - 0.5f - DC_RANGE_ROUNDING);
        y0 = ceil(r.y - 0.5f - DC_RANGE_ROUNDING);
        x1 = floor(r.z - 0.5f + DC_RANGE_ROUNDING);
        y1 = floor(r.w - 0.5f + DC_RANGE_ROUNDING);
    } else {
        /* the closed form (filter_fast) maps the footprint linearly: a projector's edges, projective
         * in the decal's space, may reach up to two pixels past the exact projection (measured) */
        const float reach = (frame->filter_fast ? 3.0f : 1.0f) + ceil(frame->filter_radius + frame->filter_step);
        x0 = floor(r.x) - reach;
        y0 = floor(r.y) - reach;
        x1 = ceil(r.z) + reach;
        y1 = ceil(r.w) + reach;
    }
    if (kept == 0 || x1 < 0.0f || y1 < 0.0f || x0 >= (float)frame->width || y0 >= (float)frame->height ||
        any(isnan(rect))) {
        b.tile_x0 = b.tile_y0 = 0;
        b.tile_x1 = b.tile_y1 = -1;
        b.pixel_x0 = b.pixel_y0 = 0;
        b.pixel_x1 = b.pixel_y1 = -1;
        b.depth_min = MAXFLOAT;
        b.depth_max = -MAXFLOAT;
    } else {
        b.tile_x0 = max(0, (int)x0 / DC_TILE_SIZE);
        b.tile_y0 = max(0, (int)y0 / DC_TILE_SIZE);
        b.tile_x1 = min(frame->tiles_x - 1, (int)x1 / DC_TILE_SIZE);
        b.tile_y1 = min(frame->tiles_y - 1, (int)y1 / DC_TILE_SIZE);
        b.pixel_x0 = max(0, (int)x0);
        b.pixel_y0 = max(0, (int)y0);
        b.pixel_x1 = min(frame->width - 1, (int)x1);
        b.pixel_y1 = min(frame->height - 1, (int)y1);
        /* taps stray up to DC_FILTER_GRAZING in depth from their pixel (pixel_filter.h) */
        const float rel = DC_DEPTH_SLACK_REL + (frame->filter_taps > 0 ? DC_FILTER_DEPTH_SLACK : 0.0f);
        b.depth_min = depth.x - fabs(depth.x) * rel - DC_DEPTH_SLACK_ABS;
        b.depth_max = depth.y + fabs(depth.y) * rel + DC_DEPTH_SLACK_ABS;
    }
    bounds[id] = b;
}

/* Binning runs at two levels, both keeping decal order: each decal marks the coarse tiles
 * (DC_COARSE_TILES x DC_COARSE_TILES tiles, shared_types.h) it overlaps; then each tile tests only
 * its coarse tile's list. Tile ranges are inclusive and in tile units at both levels. */
#if DC_DECALS_PER_MASK_WORD != 64
#error "DC_DECALS_PER_MASK_WORD must be the bit count of the ulong mask words"
#endif

inline bool dc_overlaps(DcDecalBounds b, int tx0, int ty0, int tx1, int ty1, float2 depth) {
    return tx1 >= b.tile_x0 && tx0 <= b.tile_x1 && ty1 >= b.tile_y0 && ty0 <= b.tile_y1 &&
           b.depth_min <= depth.y && b.depth_max >= depth.x;
}

inline int dc_coarse_tiles_x(__constant const DcFrame* f) {
    return (f->tiles_x + DC_COARSE_TILES - 1) / DC_COARSE_TILES;
}
inline int dc_coarse_tiles_y(__constant const DcFrame* f) {
    return (f->tiles_y + DC_COARSE_TILES - 1) / DC_COARSE_TILES;
}

/* Tiles around a tile whose depths its pixels may reach: under a pixel filter a silhouette pixel
 * takes taps on surfaces up to DC_SPLIT_WINDOW pixels away (pixel_filter.h), within one tile. */
inline int dc_depth_apron(__constant const DcFrame* f) { return f->filter_taps > 0 ? 1 : 0; }

/* Depth range of each coarse tile from its tiles' ranges (and the apron's). */
__kernel void dc_coarse_depth(__constant const DcFrame* frame, __global const float2* tile_depth,
                              __global float2* coarse_depth) {
    const int c = get_global_id(0);
    const int cx_count = dc_coarse_tiles_x(frame);
    if (c >= cx_count * dc_coarse_tiles_y(frame)) return;
    const int cx = c % cx_count, cy = c / cx_count;
    float2 r = (float2)(MAXFLOAT, -MAXFLOAT);
    const int apron = dc_depth_apron(frame);
    for (int ty = max(0, cy * DC_COARSE_TILES - apron); ty < min(frame->tiles_y, (cy + 1) * DC_COARSE_TILES + apron); ++ty)
        for (int tx = max(0, cx * DC_COARSE_TILES - apron); tx < min(frame->tiles_x, (cx + 1) * DC_COARSE_TILES + apron);
             ++tx) {
            const float2 t = tile_depth[ty * frame->tiles_x + tx];
            r = (float2)(fmin(r.x, t.x), fmax(r.y, t.y));
        }
    coarse_depth[c] = r;
}

/* Level 1 in three data-parallel steps, ordered by construction: decals are split into chunks of
 * DC_DECALS_PER_MASK_WORD, and each (coarse tile, chunk) has a mask word with a bit per decal that
 * overlaps the coarse tile. DC_MARK_LANES work-items per decal set its bits over the coarse tiles
 * its tile rectangle covers (the words start zeroed); per coarse tile the chunk popcounts are
 * prefix-summed; then each (coarse tile, chunk) writes its set bits in order. A mask word is two
 * uints, low bits first, so that 32-bit atomics (core OpenCL C) can set its bits. */
inline int dc_decal_chunks(__constant const DcFrame* f) {
    return (f->decal_count + DC_DECALS_PER_MASK_WORD - 1) / DC_DECALS_PER_MASK_WORD;
}

inline ulong dc_mask_word(__global const uint* masks, int item) {
    return (ulong)masks[2 * item] | ((ulong)masks[2 * item + 1] << 32);
}

/* Work is per decal and coarse tile it covers, not per coarse tile and decal: small decals cover
 * few coarse tiles, and a frame of many decals tests each once or a few times instead of against
 * every coarse tile. */
__kernel void dc_coarse_mark(__constant const DcFrame* frame, __global const DcDecalBounds* bounds,
                             __global const float2* coarse_depth, __global uint* masks) {
    const int d = get_global_id(0) / DC_MARK_LANES, lane = get_global_id(0) % DC_MARK_LANES;
    if (d >= frame->decal_count) return;
    const DcDecalBounds b = bounds[d];
    if (b.tile_x1 < b.tile_x0 || b.tile_y1 < b.tile_y0) return;
    const int chunks = dc_decal_chunks(frame), cx_count = dc_coarse_tiles_x(frame);
    const int cx0 = b.tile_x0 / DC_COARSE_TILES, cy0 = b.tile_y0 / DC_COARSE_TILES;
    const int columns = b.tile_x1 / DC_COARSE_TILES - cx0 + 1;
    const int covered = columns * (b.tile_y1 / DC_COARSE_TILES - cy0 + 1);
    const int word = 2 * (d / DC_DECALS_PER_MASK_WORD) + (d % DC_DECALS_PER_MASK_WORD) / 32;
    for (int j = lane; j < covered; j += DC_MARK_LANES) {
        const int cx = cx0 + j % columns, cy = cy0 + j / columns;
        const int c = cy * cx_count + cx;
        const float2 range = coarse_depth[c];
        const int tx0 = cx * DC_COARSE_TILES, ty0 = cy * DC_COARSE_TILES;
        if (range.x <= range.y &&
            dc_overlaps(b, tx0, ty0, tx0 + DC_COARSE_TILES - 1, ty0 + DC_COARSE_TILES - 1, range))
            atomic_or(&masks[2 * c * chunks + word], 1u << (d % 32));
    }
}

/* Per coarse tile, one work-group: where each chunk's entries start within the tile's list, and
 * the list length. The chunks' popcounts are prefix-summed in local memory, DC_CHUNK_LANES at a
 * time: one work-item per coarse tile walking every chunk was a chain of dependent loads. */
__kernel __attribute__((reqd_work_group_size(DC_CHUNK_LANES, 1, 1)))
void dc_coarse_count(__constant const DcFrame* frame, __global const uint* masks, __global int* chunk_starts,
                     __global int* counts) {
    __local int sums[DC_CHUNK_LANES];
    const int chunks = dc_decal_chunks(frame);
    const int c = get_group_id(0), lid = get_local_id(0);
    if (c >= dc_coarse_tiles_x(frame) * dc_coarse_tiles_y(frame)) return; /* the whole group */
    int base = 0;
    for (int k0 = 0; k0 < chunks; k0 += DC_CHUNK_LANES) {
        const int k = k0 + lid;
        const int own = k < chunks ? (int)popcount(dc_mask_word(masks, c * chunks + k)) : 0;
        int block;
        const int inclusive = dc_group_scan(sums, own, DC_CHUNK_LANES, &block);
        if (k < chunks) chunk_starts[c * chunks + k] = base + inclusive - own;
        base += block;
    }
    if (lid == 0) counts[c] = base;
}

/* The same, one work-item per coarse tile walking its chunks: for CPU devices, where work-group
 * barriers cost more than the walk (the host picks, compositor.cpp). */
__kernel void dc_coarse_count_serial(__constant const DcFrame* frame, __global const uint* masks,
                                     __global int* chunk_starts, __global int* counts) {
    const int chunks = dc_decal_chunks(frame);
    const int c = get_global_id(0);
    if (c >= dc_coarse_tiles_x(frame) * dc_coarse_tiles_y(frame)) return;
    int n = 0;
    for (int k = 0; k < chunks; ++k) {
        chunk_starts[c * chunks + k] = n;
        n += (int)popcount(dc_mask_word(masks, c * chunks + k));
    }
    counts[c] = n;
}

/* `capacity` entries fit in `lists`; the host compares the total (offsets[count]) with it after
 * the frame and, when it did not fit, grows the list and runs the frame again. */
__kernel void dc_coarse_fill(__constant const DcFrame* frame, __global const uint* masks,
                             __global const int* chunk_starts, __global const int* offsets,
                             __global int* lists, int capacity) {
    const int chunks = dc_decal_chunks(frame);
    const int item = get_global_id(0);
    if (item >= dc_coarse_tiles_x(frame) * dc_coarse_tiles_y(frame) * chunks) return;
    const int c = item / chunks, k = item % chunks;
    ulong bits = dc_mask_word(masks, item);
    int next = offsets[c] + chunk_starts[item];
    while (bits != 0 && next < capacity) {
        const int bit = (int)(63 - clz(bits & (~bits + 1))); /* lowest set bit */
        lists[next++] = k * DC_DECALS_PER_MASK_WORD + bit;
        bits &= bits - 1;
    }
}

/* Level 2 also tests each decal's own volume: when a point-sampled frame's points lie on their
 * pixels' rays (every convention but position), a tile's points lie inside the frustum piece of its
 * rectangle and depth range, the hull of 8 corners. A decal whose volume lies wholly beyond one of
 * its own bounding planes from all 8 misses every pixel of the tile: turned decals list far fewer
 * tiles than their screen rectangles cover (docs/benchmarks.md). */
typedef struct {
    float3 corner[8];
    float radius; /* the largest |corner|: bounds every point of the tile */
    int valid;
} DcTileHull;

/* `range`: the tile's view depths, not empty. */
inline DcTileHull dc_tile_hull(__constant const DcFrame* f, int tx, int ty, float2 range) {
    DcTileHull h;
    h.valid = f->filter_taps == 0 && f->depth_convention != DC_DEPTH_POSITION;
    h.radius = 0.0f;
    if (!h.valid) return h;
    /* the pixel centres lie half a pixel inside the tile's edges; depths get the bounds' slack */
    const float x0 = (float)(tx * DC_TILE_SIZE), y0 = (float)(ty * DC_TILE_SIZE);
    const float x1 = (float)min(f->width, (tx + 1) * DC_TILE_SIZE), y1 = (float)min(f->height, (ty + 1) * DC_TILE_SIZE);
    const float z0 = fmax(range.x - fabs(range.x) * DC_DEPTH_SLACK_REL - DC_DEPTH_SLACK_ABS, 0.0f);
    const float z1 = range.y + fabs(range.y) * DC_DEPTH_SLACK_REL + DC_DEPTH_SLACK_ABS;
    for (int i = 0; i < 8; ++i) {
        const float2 ndc = dc_ndc_at(f, (i & 1) ? x1 : x0, (i & 2) ? y1 : y0);
        h.corner[i] = dc_point_at_view_depth(f, ndc, (i & 4) ? z1 : z0);
        h.radius = fmax(h.radius, length(h.corner[i]));
    }
    h.valid = !isnan(h.radius) && !isinf(h.radius);
    return h;
}

/* Whether the tile's hull lies wholly outside one of decal d's bounding planes (in its local
 * space: the unit box's faces, which also bound a cube's sphere; a frustum's six planes). The
 * margin covers the rounding of the shading kernel's own local coordinates, whose error grows with
 * the point's and the decal's offsets. */
inline bool dc_hull_misses(__global const DcDecal* d, const DcTileHull* h) {
    __global const float* m = d->camera_to_local;
    const float scale = fmax(d->local_scale[0], fmax(d->local_scale[1], d->local_scale[2]));
    const float offset = fmax(fabs(m[3]), fmax(fabs(m[7]), fabs(m[11])));
    const bool frustum = d->kind == DC_KIND_FRUSTUM;
    const float slope_x = frustum ? d->tan_half_fov_y * d->aspect : 0.0f, slope_y = frustum ? d->tan_half_fov_y : 0.0f;
    const float margin = 1e-4f * (scale * h->radius + offset) * (1.0f + slope_x + slope_y) + 1e-6f;
    /* per plane, the least excess over all corners; the tile misses when some plane's is positive */
    float least[6];
    for (int k = 0; k < 6; ++k) least[k] = MAXFLOAT;
    for (int i = 0; i < 8; ++i) {
        const float3 l = dc_affine_global(m, h->corner[i]);
        float e[6];
        if (frustum) {
            const float dist = -l.z;
            e[0] = l.x - dist * slope_x;
            e[1] = -l.x - dist * slope_x;
            e[2] = l.y - dist * slope_y;
            e[3] = -l.y - dist * slope_y;
            e[4] = d->near_plane - dist;
            e[5] = dist - d->far_plane;
        } else {
            e[0] = l.x - 0.5f;
            e[1] = -l.x - 0.5f;
            e[2] = l.y - 0.5f;
            e[3] = -l.y - 0.5f;
            e[4] = l.z - 0.5f;
            e[5] = -l.z - 0.5f;
        }
        for (int k = 0; k < 6; ++k) least[k] = fmin(least[k], e[k]);
    }
    for (int k = 0; k < 6; ++k)
        if (least[k] > margin) return true;
    return false;
}

/* Level 2: each tile against its coarse tile's list. The count pass tests each entry
 * and leaves one flag per (entry, tile of the coarse tile) in `listed`: the fill pass then reads
 * the flags instead of testing again. */
inline size_t dc_listed_flag(__constant const DcFrame* frame, int entry, int tile) {
    const int tx = tile % frame->tiles_x, ty = tile / frame->tiles_x;
    return (size_t)entry * (DC_COARSE_TILES * DC_COARSE_TILES) + (ty % DC_COARSE_TILES) * DC_COARSE_TILES +
           tx % DC_COARSE_TILES;
}

/* The coarse tile holding `tile`. */
inline int dc_coarse_of_tile(__constant const DcFrame* frame, int tile) {
    const int tx = tile % frame->tiles_x, ty = tile / frame->tiles_x;
    return (ty / DC_COARSE_TILES) * dc_coarse_tiles_x(frame) + tx / DC_COARSE_TILES;
}

/* A tile's view depths with its apron's (dc_depth_apron); not empty only where the tile has a
 * surface pixel (`surface`). */
inline float2 dc_tile_range(__constant const DcFrame* frame, __global const float2* tile_depth, int tx, int ty,
                            bool* surface) {
    float2 range = tile_depth[ty * frame->tiles_x + tx];
    *surface = range.x <= range.y; /* else no pixel to shade, and nothing listed */
    if (!*surface) return range;
    const int apron = dc_depth_apron(frame);
    for (int ny = max(0, ty - apron); ny <= min(frame->tiles_y - 1, ty + apron); ++ny)
        for (int nx = max(0, tx - apron); nx <= min(frame->tiles_x - 1, tx + apron); ++nx) {
            const float2 t = tile_depth[ny * frame->tiles_x + nx];
            range = (float2)(fmin(range.x, t.x), fmax(range.y, t.y));
        }
    return range;
}

/* Whether decal d of the coarse list reaches tile (tx, ty) of depth `range` and `hull`. */
inline bool dc_tile_lists(__global const DcDecal* decals, __global const DcDecalBounds* bounds, int d, int tx,
                          int ty, float2 range, const DcTileHull* hull) {
    return dc_overlaps(bounds[d], tx, ty, tx, ty, range) &&
           !(hull->valid && decals[d].rest_binding < 0 && dc_hull_misses(&decals[d], hull));
}

/* One work-group per tile, its DC_BIN_LANES work-items over the coarse list's entries (one
 * work-item per tile walking the list was a chain of tests too short of work-items for a GPU). */
__kernel __attribute__((reqd_work_group_size(DC_BIN_LANES, 1, 1)))
void dc_bin_count(__constant const DcFrame* frame, __global const DcDecal* decals,
                  __global const DcDecalBounds* bounds, __global const float2* tile_depth,
                  __global const int* coarse_offsets, __global const int* coarse_lists, int coarse_capacity,
                  __global uchar* listed, __global int* counts) {
    __local DcTileHull shared_hull[1]; /* work-item 0's, for all */
    __local int sums[DC_BIN_LANES];
    const int tile = get_group_id(0), lid = get_local_id(0);
    if (tile >= frame->tiles_x * frame->tiles_y) return; /* the whole group */
    const int tx = tile % frame->tiles_x, ty = tile / frame->tiles_x, c = dc_coarse_of_tile(frame, tile);
    /* an overflowed coarse list is read only up to its capacity: the frame runs again anyway */
    const int begin = coarse_offsets[c], end = min(coarse_offsets[c + 1], coarse_capacity);
    bool surface;
    const float2 range = dc_tile_range(frame, tile_depth, tx, ty, &surface);
    if (lid == 0) {
        shared_hull[0].valid = 0;
        if (surface && begin < end) shared_hull[0] = dc_tile_hull(frame, tx, ty, range);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    const DcTileHull hull = shared_hull[0];
    int n = 0;
    for (int k = begin + lid; k < end; k += DC_BIN_LANES) {
        const bool in = surface && dc_tile_lists(decals, bounds, coarse_lists[k], tx, ty, range, &hull);
        listed[dc_listed_flag(frame, k, tile)] = in ? 1 : 0;
        n += in ? 1 : 0;
    }
    int listed_here;
    dc_group_scan(sums, n, DC_BIN_LANES, &listed_here);
    if (lid == 0) counts[tile] = listed_here;
}

/* The same, one work-item per tile walking the list: for CPU devices (as dc_coarse_count_serial). */
__kernel void dc_bin_count_serial(__constant const DcFrame* frame, __global const DcDecal* decals,
                                  __global const DcDecalBounds* bounds, __global const float2* tile_depth,
                                  __global const int* coarse_offsets, __global const int* coarse_lists,
                                  int coarse_capacity, __global uchar* listed, __global int* counts) {
    const int tile = get_global_id(0);
    if (tile >= frame->tiles_x * frame->tiles_y) return;
    const int tx = tile % frame->tiles_x, ty = tile / frame->tiles_x, c = dc_coarse_of_tile(frame, tile);
    const int begin = coarse_offsets[c], end = min(coarse_offsets[c + 1], coarse_capacity);
    bool surface;
    const float2 range = dc_tile_range(frame, tile_depth, tx, ty, &surface);
    DcTileHull hull;
    hull.valid = 0;
    if (surface && begin < end) hull = dc_tile_hull(frame, tx, ty, range);
    int n = 0;
    for (int k = begin; k < end; ++k) {
        const bool in = surface && dc_tile_lists(decals, bounds, coarse_lists[k], tx, ty, range, &hull);
        listed[dc_listed_flag(frame, k, tile)] = in ? 1 : 0;
        n += in ? 1 : 0;
    }
    counts[tile] = n;
}

/* `capacity` entries fit in `tile_decals` from the prefix-summed `offsets`. */
__kernel void dc_bin_fill(__constant const DcFrame* frame, __global const int* coarse_offsets,
                          __global const int* coarse_lists, int coarse_capacity, __global const uchar* listed,
                          __global const int* offsets, __global int* tile_decals, int capacity) {
    const int tile = get_global_id(0);
    if (tile >= frame->tiles_x * frame->tiles_y) return;
    const int c = dc_coarse_of_tile(frame, tile);
    const int begin = coarse_offsets[c], end = min(coarse_offsets[c + 1], coarse_capacity);
    int next = offsets[tile];
    for (int k = begin; k < end && next < capacity; ++k)
        if (listed[dc_listed_flag(frame, k, tile)]) tile_decals[next++] = coarse_lists[k];
}

#endif /* DC_SHADING_PROGRAM */
