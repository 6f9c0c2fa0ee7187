/* Sums over a work-group in local memory, for the binning's prefix sums (scan.cl, binning.cl). */
#ifndef DECALCOMP_WORK_GROUP_H
#define DECALCOMP_WORK_GROUP_H

/* The inclusive prefix sum of `value` over the work-group's `lanes` work-items (Hillis-Steele,
 * through `sums`, which holds `lanes` ints); *total gets the whole group's sum. Every work-item of
 * the group must call it; `sums` is free again when it returns. */
inline int dc_group_scan(__local int* sums, int value, int lanes, int* total) {
    const int lid = get_local_id(0);
    sums[lid] = value;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int stride = 1; stride < lanes; stride <<= 1) {
        const int add = lid >= stride ? sums[lid - stride] : 0;
        barrier(CLK_LOCAL_MEM_FENCE);
        sums[lid] += add;
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    const int inclusive = sums[lid];
    *total = sums[lanes - 1];
    barrier(CLK_LOCAL_MEM_FENCE);
    return inclusive;
}

#endif
