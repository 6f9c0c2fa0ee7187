/* Exclusive prefix sum of `n` counts with the total appended (`offsets` has n + 1 entries), in
 * one work-group, so the host never waits for the counts in the middle of a frame. The counts go
 * through local memory in blocks of DC_SCAN_GROUP * DC_SCAN_RUN: read and written coalesced (each
 * work-item takes every DC_SCAN_GROUP-th count), summed and offset in runs of DC_SCAN_RUN per
 * work-item, the runs' sums scanned in local memory (Hillis-Steele), each block from the carry of
 * the ones before. Lists are at most a few hundred thousand tiles. (Each work-item reading its own
 * run from global memory, uncoalesced, took 0.043 ms of a 4K frame on an H100; this takes 0.017:
 * docs/benchmarks.md, stop 43.) */
#include "shared_types.h"
#include "work_group.h"

/* A shading program (ComputeDevice::shadingProgram) holds its dc_shade alone. */
#ifndef DC_SHADING_PROGRAM

#define DC_SCAN_RUN 16
#define DC_SCAN_BLOCK (DC_SCAN_GROUP * DC_SCAN_RUN)
/* Where count q of a block lies in local memory: a word of padding after each run, so that the
 * work-items reading their runs side by side hit different banks. */
#define DC_SCAN_SLOT(q) ((q) + (q) / DC_SCAN_RUN)

__kernel __attribute__((reqd_work_group_size(DC_SCAN_GROUP, 1, 1)))
void dc_scan(__global const int* counts, int n, __global int* offsets) {
    __local int block[DC_SCAN_BLOCK + DC_SCAN_GROUP];
    __local int sums[DC_SCAN_GROUP];
    const int lid = get_local_id(0);
    int carry = 0;
    for (int start = 0; start < n; start += DC_SCAN_BLOCK) {
        for (int r = 0; r < DC_SCAN_RUN; ++r) {
            const int i = start + r * DC_SCAN_GROUP + lid;
            block[DC_SCAN_SLOT(r * DC_SCAN_GROUP + lid)] = i < n ? counts[i] : 0;
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        int sum = 0;
        for (int r = 0; r < DC_SCAN_RUN; ++r) sum += block[DC_SCAN_SLOT(lid * DC_SCAN_RUN + r)];
        int total;
        int next = carry + dc_group_scan(sums, sum, DC_SCAN_GROUP, &total) - sum; /* the runs before */
        for (int r = 0; r < DC_SCAN_RUN; ++r) {
            const int count = block[DC_SCAN_SLOT(lid * DC_SCAN_RUN + r)];
            block[DC_SCAN_SLOT(lid * DC_SCAN_RUN + r)] = next;
            next += count;
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        for (int r = 0; r < DC_SCAN_RUN; ++r) {
            const int i = start + r * DC_SCAN_GROUP + lid;
            if (i < n) offsets[i] = block[DC_SCAN_SLOT(r * DC_SCAN_GROUP + lid)];
        }
        carry += total;
        barrier(CLK_LOCAL_MEM_FENCE); /* the block is read before the next one overwrites it */
    }
    if (lid == 0) offsets[n] = carry;
}

#endif /* DC_SHADING_PROGRAM */
