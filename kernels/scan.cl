/* Exclusive prefix sum of `n` counts with the total appended (`offsets` has n + 1 entries), in
 * one work-group, so the host never waits for the counts in the middle of a frame. Each
 * work-item sums a contiguous run, the runs' sums are scanned in local memory (Hillis-Steele),
 * then each work-item writes its run's offsets. Lists are at most a few hundred thousand tiles. */
#include "shared_types.h"
#include "work_group.h"

/* A shading program (ComputeDevice::shadingProgram) holds its dc_shade alone. */
#ifndef DC_SHADING_PROGRAM

__kernel __attribute__((reqd_work_group_size(DC_SCAN_GROUP, 1, 1)))
void dc_scan(__global const int* counts, int n, __global int* offsets) {
    __local int sums[DC_SCAN_GROUP];
    const int lid = get_local_id(0);
    const int run = (n + DC_SCAN_GROUP - 1) / DC_SCAN_GROUP;
    const int first = min(n, lid * run), last = min(n, first + run);
    int sum = 0;
    for (int i = first; i < last; ++i) sum += counts[i];
    int total;
    int next = dc_group_scan(sums, sum, DC_SCAN_GROUP, &total) - sum; /* the runs before this one */
    for (int i = first; i < last; ++i) {
        offsets[i] = next;
        next += counts[i];
    }
    if (lid == DC_SCAN_GROUP - 1) offsets[n] = total;
}

#endif /* DC_SHADING_PROGRAM */
