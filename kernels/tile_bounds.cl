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

    float lo = MAXFLOAT, hi = -MAXFLOAT;
    float3 p;
    if (x < frame->width && y < frame->height &&
        dc_reconstruct(frame, depth_plane, position_plane, x, y, &p)) {
        lo = -p.z;
        hi = -p.z;
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
