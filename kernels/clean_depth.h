/* Clean pixels (docs/pixel-filter.md "Silhouettes"): a surface pixel whose 4-neighbours are all
 * surfaces within DC_CLEAN_DEPTH_STEP of its view depth. The split of a mixed pixel scans a window
 * for them, and the crease's scan three times over: dc_clean_depths marks every pixel once per
 * frame on GPUs, so that a scan reads one float per neighbour instead of five depths
 * (docs/benchmarks.md). */
#ifndef DECALCOMP_CLEAN_DEPTH_H
#define DECALCOMP_CLEAN_DEPTH_H

#include "shared_types.h"
#include "reconstruct.h"

#define DC_CLEAN_DEPTH_STEP 0.015f

/* The largest view-depth step from pixel (x, y) at view depth z to its 4-neighbours in the frame;
 * MAXFLOAT where one of them has no point. */
inline float dc_depth_step(__constant const DcFrame* f, __global const float* depth_plane,
                           __global const float4* position_plane, int x, int y, float z) {
    float step = 0.0f;
    for (int k = 0; k < 4; ++k) {
        const int nx = x + (k == 0) - (k == 1), ny = y + (k == 2) - (k == 3);
        float zn;
        if (nx < 0 || ny < 0 || nx >= f->width || ny >= f->height) continue;
        if (!dc_view_depth(f, depth_plane, position_plane, nx, ny, &zn)) return MAXFLOAT;
        step = fmax(step, fabs(zn - z));
    }
    return step;
}

/* Pixel (x, y)'s view depth where it is clean; NaN where it is not (background, or a step). */
inline float dc_clean_depth(__constant const DcFrame* f, __global const float* depth_plane,
                            __global const float4* position_plane, int x, int y) {
    float z;
    if (!dc_view_depth(f, depth_plane, position_plane, x, y, &z) ||
        !(dc_depth_step(f, depth_plane, position_plane, x, y, z) <= DC_CLEAN_DEPTH_STEP * z))
        return NAN;
    return z;
}

/* Whether pixel (x, y) is clean, its view depth in *z: from dc_clean_depths' plane where the frame
 * has one (GPUs, where the window scans are latency), else tested here (CPU devices, where the
 * pass over every pixel cost more than the scans it saves). */
inline bool dc_clean_at(__constant const DcFrame* f, __global const float* clean_depths,
                        __global const float* depth_plane, __global const float4* position_plane, int x, int y,
                        float* z) {
    *z = f->clean_plane ? clean_depths[(size_t)y * f->width + x] : dc_clean_depth(f, depth_plane, position_plane, x, y);
    return !isnan(*z);
}

#endif
