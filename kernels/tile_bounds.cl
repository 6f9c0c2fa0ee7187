/* Per-tile planar depth range of the pixels that are not background: one work-group of
 * DC_TILE_SIZE x DC_TILE_SIZE work-items per tile, reduced in local memory.
 * Empty tiles get (+MAXFLOAT, -MAXFLOAT). */
#include "shared_types.h"
#include "frame_reads.h"
#include "matrix.h"
#include "reconstruct.h"

/* A shading program (ComputeDevice::shadingProgram) holds its dc_shade alone. */
#ifndef DC_SHADING_PROGRAM

__kernel __attribute__((reqd_work_group_size(DC_TILE_SIZE, DC_TILE_SIZE, 1)))
void dc_tile_bounds(__constant const DcFrame* frame, __global const float* depth_plane,
                    __global const float4* position_plane, __global float2* tile_depth) {
    __local float local_min[DC_TILE_SIZE * DC_TILE_SIZE];
    __local float local_max[DC_TILE_SIZE * DC_TILE_SIZE];
    const int x = get_global_id(0), y = get_global_id(1);
    const int lid = get_local_id(1) * DC_TILE_SIZE + get_local_id(0);

    float lo = MAXFLOAT, hi = -MAXFLOAT, z;
    if (x < frame->width && y < frame->height && dc_view_depth(frame, depth_plane, position_plane, x, y, &z)) {
        lo = z;
        hi = z;
    }
    local_min[lid] = lo;
    local_max[lid] = hi;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int stride = DC_TILE_SIZE * DC_TILE_SIZE / 2; stride > 0; stride >>= 1) {
        if (lid < stride) {
            local_min[lid] = fmin(local_min[lid], local_min[lid + stride]);
            local_max[lid] = fmax(local_max[lid], local_max[lid + stride]);
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (lid == 0)
        tile_depth[get_group_id(1) * frame->tiles_x + get_group_id(0)] = (float2)(local_min[0], local_max[0]);
}

/* The same ranges with one work-item per tile walking its pixels: no local memory and no
 * barriers, which CPU devices (PoCL) run several times faster than the work-group reduction. */
__kernel void dc_tile_bounds_serial(__constant const DcFrame* frame, __global const float* depth_plane,
                                    __global const float4* position_plane, __global float2* tile_depth) {
    const int tile = get_global_id(0);
    if (tile >= frame->tiles_x * frame->tiles_y) return;
    const int x0 = (tile % frame->tiles_x) * DC_TILE_SIZE, y0 = (tile / frame->tiles_x) * DC_TILE_SIZE;
    const int x1 = min(x0 + DC_TILE_SIZE, frame->width), y1 = min(y0 + DC_TILE_SIZE, frame->height);
    float lo = MAXFLOAT, hi = -MAXFLOAT;
    if (frame->depth_convention == DC_DEPTH_PLANAR && frame->has_depth && x1 - x0 == DC_TILE_SIZE) {
        /* planar depth, a whole tile row at a time (the test of dc_view_depth, vectorised) */
        const float near_limit = frame->orthographic ? -MAXFLOAT : DC_MIN_VIEW_DEPTH * (1.0f - 1e-5f);
        const float far_limit = frame->far_plane > 0.0f ? frame->far_plane * (1.0f + 1e-5f) : MAXFLOAT;
        /* valid: d > 0 and d >= the near limit, d < the background depth and d <= the far limit; as
         * one test each way, d > lower and d <= upper (which also leaves out infinities and NaN) */
        const float near_bound = fmax(near_limit, 0.0f);
        const float16 lower = (float16)(near_bound > 0.0f ? nextafter(near_bound, 0.0f) : 0.0f);
        const float16 upper = (float16)(fmin(far_limit, nextafter(DC_BACKGROUND_DEPTH, 0.0f)));
        float16 lo16 = (float16)(MAXFLOAT), hi16 = (float16)(-MAXFLOAT);
        /* Work-items walk the tiles along x, each row a stream 64 bytes a tile: each row's line
         * four tiles on is read ahead (dc_touch), so that it is in the cache when its tile comes
         * (PoCL: 14 % faster at 1080p). */
        const int ahead = min(x0 + 4 * DC_TILE_SIZE, frame->width - 1) - x0;
        for (int y = y0; y < y1; ++y) {
            const __global float* row = depth_plane + (size_t)y * frame->width + x0;
            dc_touch(row + ahead);
            const float16 d = vload16(0, row);
            const int16 valid = (d > lower) & (d <= upper);
            lo16 = select(lo16, fmin(lo16, d), valid);
            hi16 = select(hi16, fmax(hi16, d), valid);
        }
        float8 l8 = fmin(lo16.lo, lo16.hi), h8 = fmax(hi16.lo, hi16.hi);
        float4 l4 = fmin(l8.lo, l8.hi), h4 = fmax(h8.lo, h8.hi);
        float2 l2 = fmin(l4.lo, l4.hi), h2 = fmax(h4.lo, h4.hi);
        tile_depth[tile] = (float2)(fmin(l2.x, l2.y), fmax(h2.x, h2.y));
        return;
    }
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            float z;
            if (dc_view_depth(frame, depth_plane, position_plane, x, y, &z)) {
                lo = fmin(lo, z);
                hi = fmax(hi, z);
            }
        }
    tile_depth[tile] = (float2)(lo, hi);
}

#endif /* DC_SHADING_PROGRAM */
