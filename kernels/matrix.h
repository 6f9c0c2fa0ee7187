/* Row-major matrix helpers; rows are loaded with vload4 so any float alignment works. */
#ifndef DECALCOMP_MATRIX_H
#define DECALCOMP_MATRIX_H

/* 4x4 row-major matrix (in __constant memory) times a column vector. */
inline float4 dc_mul4_constant(__constant const float* m, float4 v) {
    return (float4)(dot(vload4(0, m), v), dot(vload4(1, m), v), dot(vload4(2, m), v),
                    dot(vload4(3, m), v));
}

/* The top 3 rows of an affine row-major matrix (12 floats) applied to a point. */
inline float3 dc_affine_global(__global const float* m, float3 p) {
    const float4 v = (float4)(p, 1.0f);
    return (float3)(dot(vload4(0, m), v), dot(vload4(1, m), v), dot(vload4(2, m), v));
}

inline float3 dc_affine_constant(__constant const float* m, float3 p) {
    const float4 v = (float4)(p, 1.0f);
    return (float3)(dot(vload4(0, m), v), dot(vload4(1, m), v), dot(vload4(2, m), v));
}

#endif
