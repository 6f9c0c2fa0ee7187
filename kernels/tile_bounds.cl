/* Per-tile planar depth range of the pixels that are not background: one work-group of
 * DC_TILE_SIZE x DC_TILE_SIZE work-items per tile, reduced in local memory.
 * Empty tiles get (+MAXFLOAT, -MAXFLOAT). */
#include "shared_types.h"
#include "matrix.h"
#include "reconstruct.h"

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
