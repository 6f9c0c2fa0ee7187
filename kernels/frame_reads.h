/* How kernels read a frame's planes: which surface groups the frame carries, and on CPU devices
 * lines read ahead of their use. */
#ifndef DECALCOMP_FRAME_READS_H
#define DECALCOMP_FRAME_READS_H

#include "shared_types.h"

/* Whether the frame carries the surface group (world normal, metallic), the second float4 plane. */
inline bool dc_has_group1(__constant const DcFrame* f) {
    return (f->attributes & ((1 << DC_TARGET_NORMAL) | (1 << DC_TARGET_METALLIC))) != 0;
}

/* Whether the frame carries the surface group (emission, ao), the third float4 plane. */
inline bool dc_has_group2(__constant const DcFrame* f) {
    return (f->attributes & ((1 << DC_TARGET_EMISSION) | (1 << DC_TARGET_AO))) != 0;
}

/* Reads the line holding *p ahead of its use and drops the value: a plain load, since OpenCL C
 * 1.2's prefetch() does nothing on PoCL. On a CPU the miss then overlaps the work before the use
 * (docs/decisions.md "Kernels shaped for CPU devices"). */
inline void dc_touch(const __global float* p) { (void)*(const volatile __global float*)p; }

#endif
