/* Filtered frames: every pixel's view depth where it is clean, NaN elsewhere (clean_depth.h), for
 * the shading kernel's window scans. A work-item per pixel. */
#include "shared_types.h"
#include "clean_depth.h"

/* A shading program (ComputeDevice::shadingProgram) holds its dc_shade alone. */
#ifndef DC_SHADING_PROGRAM

__kernel void dc_clean_depths(__constant const DcFrame* frame, __global const float* depth_plane,
                              __global const float4* position_plane, __global float* clean_depths) {
    const int x = get_global_id(0), y = get_global_id(1);
    if (x >= frame->width || y >= frame->height) return;
    clean_depths[(size_t)y * frame->width + x] = dc_clean_depth(frame, depth_plane, position_plane, x, y);
}

#endif
