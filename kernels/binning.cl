/* Binning: each decal's conservative screen footprint, then per-tile decal lists in two passes
 * (count, then fill at offsets from a prefix sum), so lists keep decal order and never drop one. */
#include "shared_types.h"
#include "matrix.h"

/* Relative and absolute slack on depth ranges, for float rounding in both sides of the test. */
#define DC_DEPTH_SLACK_REL 1e-4f
#define DC_DEPTH_SLACK_ABS 1e-6f

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
    for (int i = 0; i < 8; ++i) {
        const float3 local_point = (float3)((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f);
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
    b.pad0 = b.pad1 = 0;
    const float big = 1e9f; /* keeps pixel coordinates in int range */
    const float x0 = floor(clamp(rect.x, -big, big)) - 1.0f, y0 = floor(clamp(rect.y, -big, big)) - 1.0f;
    const float x1 = ceil(clamp(rect.z, -big, big)) + 1.0f, y1 = ceil(clamp(rect.w, -big, big)) + 1.0f;
    if (kept == 0 || x1 < 0.0f || y1 < 0.0f || x0 >= (float)frame->width || y0 >= (float)frame->height ||
        any(isnan(rect))) {
        b.tile_x0 = b.tile_y0 = 0;
        b.tile_x1 = b.tile_y1 = -1;
        b.depth_min = MAXFLOAT;
        b.depth_max = -MAXFLOAT;
    } else {
        b.tile_x0 = max(0, (int)x0 / DC_TILE_SIZE);
        b.tile_y0 = max(0, (int)y0 / DC_TILE_SIZE);
        b.tile_x1 = min(frame->tiles_x - 1, (int)x1 / DC_TILE_SIZE);
        b.tile_y1 = min(frame->tiles_y - 1, (int)y1 / DC_TILE_SIZE);
        b.depth_min = depth.x - fabs(depth.x) * DC_DEPTH_SLACK_REL - DC_DEPTH_SLACK_ABS;
        b.depth_max = depth.y + fabs(depth.y) * DC_DEPTH_SLACK_REL + DC_DEPTH_SLACK_ABS;
    }
    bounds[id] = b;
}

inline bool dc_overlaps(DcDecalBounds b, int tx, int ty, float2 tile_depth) {
    return tx >= b.tile_x0 && tx <= b.tile_x1 && ty >= b.tile_y0 && ty <= b.tile_y1 &&
           b.depth_min <= tile_depth.y && b.depth_max >= tile_depth.x;
}

/* Decals per tile, staged through local_point memory in chunks shared by the work-group. */
#define DC_BIN_CHUNK 64

__kernel void dc_bin_count(__constant const DcFrame* frame, __global const DcDecalBounds* bounds,
                           __global const float2* tile_depth, __global int* counts) {
    __local DcDecalBounds chunk[DC_BIN_CHUNK];
    const int tile = get_global_id(0);
    const int tile_count = frame->tiles_x * frame->tiles_y;
    const bool active = tile < tile_count;
    const float2 range = active ? tile_depth[tile] : (float2)(MAXFLOAT, -MAXFLOAT);
    const int tx = active ? tile % frame->tiles_x : 0, ty = active ? tile / frame->tiles_x : 0;
    int count = 0;
    for (int base = 0; base < frame->decal_count; base += DC_BIN_CHUNK) {
        const int n = min(DC_BIN_CHUNK, frame->decal_count - base);
        barrier(CLK_LOCAL_MEM_FENCE);
        for (int i = get_local_id(0); i < n; i += get_local_size(0)) chunk[i] = bounds[base + i];
        barrier(CLK_LOCAL_MEM_FENCE);
        if (active && range.x <= range.y)
            for (int i = 0; i < n; ++i) count += dc_overlaps(chunk[i], tx, ty, range) ? 1 : 0;
    }
    if (active) counts[tile] = count;
}

__kernel void dc_bin_fill(__constant const DcFrame* frame, __global const DcDecalBounds* bounds,
                          __global const float2* tile_depth, __global const int* offsets,
                          __global int* tile_decals) {
    __local DcDecalBounds chunk[DC_BIN_CHUNK];
    const int tile = get_global_id(0);
    const int tile_count = frame->tiles_x * frame->tiles_y;
    const bool active = tile < tile_count;
    const float2 range = active ? tile_depth[tile] : (float2)(MAXFLOAT, -MAXFLOAT);
    const int tx = active ? tile % frame->tiles_x : 0, ty = active ? tile / frame->tiles_x : 0;
    int next = active ? offsets[tile] : 0;
    for (int base = 0; base < frame->decal_count; base += DC_BIN_CHUNK) {
        const int n = min(DC_BIN_CHUNK, frame->decal_count - base);
        barrier(CLK_LOCAL_MEM_FENCE);
        for (int i = get_local_id(0); i < n; i += get_local_size(0)) chunk[i] = bounds[base + i];
        barrier(CLK_LOCAL_MEM_FENCE);
        if (active && range.x <= range.y)
            for (int i = 0; i < n; ++i)
                if (dc_overlaps(chunk[i], tx, ty, range)) tile_decals[next++] = base + i;
    }
}
