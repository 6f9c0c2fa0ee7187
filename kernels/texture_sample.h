/* Texture lookups in the packed texel buffer: clamp-to-edge addressing (cube faces: seamless
 * linear filtering across faces), texel centres at (i + 0.5) / width, t = 0 on the image's top
 * row. A texture has `depth` slices of width x height texels: 1 for 2D images, D for volumes,
 * 6 for cube faces. */
#ifndef DECALCOMP_TEXTURE_SAMPLE_H
#define DECALCOMP_TEXTURE_SAMPLE_H

#include "shared_types.h"

inline float4 dc_texel(__global const float4* texels, DcTexture t, int i, int j, int slice) {
    i = clamp(i, 0, t.width - 1);
    j = clamp(j, 0, t.height - 1);
    slice = clamp(slice, 0, t.depth - 1);
    return texels[t.offset + (slice * t.height + j) * t.width + i];
}

/* floor() of a value already clamped to a texture's size: exact there, without the generic floor's
 * paths for NaN and huge values (PoCL's CPU device runs those in software: texture lookups took
 * 13 % less time without them, docs/benchmarks.md). */
inline float dc_floor_clamped(float v) {
    const float t = (float)(int)v;
    return t > v ? t - 1.0f : t;
}

/* Texel index along one axis for nearest lookup; clamped in float so huge inputs cannot overflow. */
inline int dc_nearest_index(float coord, int size) {
    return (int)dc_floor_clamped(clamp(coord * (float)size, -1.0f, (float)size));
}

/* Bilinear weights around (s W - 0.5, t H - 0.5): the four taps' indices and fractions. */
#define DC_BILINEAR(TAP)                                                        \
    const float x = clamp(s * (float)t.width - 0.5f, -1.0f, (float)t.width);    \
    const float y = clamp(tc * (float)t.height - 0.5f, -1.0f, (float)t.height); \
    const float x0 = dc_floor_clamped(x), y0 = dc_floor_clamped(y);             \
    const float fx = x - x0, fy = y - y0;                                       \
    const int i = (int)x0, j = (int)y0;                                         \
    return mix(mix(TAP(i, j), TAP(i + 1, j), fx), mix(TAP(i, j + 1), TAP(i + 1, j + 1), fx), fy)

/* 2D lookup within one slice. */
DC_INLINE float4 dc_sample_slice(__global const float4* texels, DcTexture t, float s, float tc, int slice,
                                 int filter) {
    if (filter == DC_FILTER_NEAREST)
        return dc_texel(texels, t, dc_nearest_index(s, t.width), dc_nearest_index(tc, t.height), slice);
#define DC_SLICE_TAP(a, b) dc_texel(texels, t, (a), (b), slice)
    DC_BILINEAR(DC_SLICE_TAP);
#undef DC_SLICE_TAP
}

/* Nearest texels integrated exactly over a box `rho` texels wide per axis (rho <= 2, so the box
 * spans at most three texels per axis) centred on (s, tc): a tap's stratum. */
inline float dc_box_share(float lo, float hi, float texel) { /* of [lo, hi] inside [texel, texel + 1] */
    return fmax(0.0f, fmin(hi, texel + 1.0f) - fmax(lo, texel));
}

DC_INLINE float4 dc_sample_slice_box(__global const float4* texels, DcTexture t, float s, float tc, int slice,
                                     float2 rho) {
    const float2 c = (float2)(clamp(s * (float)t.width, -1.0f, (float)t.width + 1.0f),
                              clamp(tc * (float)t.height, -1.0f, (float)t.height + 1.0f));
    const float2 r = fmax(rho, (float2)(1e-6f));
    if (r.x <= 1.0f && r.y <= 1.0f) {
        /* A box at most one texel wide crosses at most the texel edge b nearest its centre: the
         * texels on either side share it as a linear ramp, a bilinear lookup with sharpened
         * fractions (the common case: a filter stratum is half a pixel). */
        const float2 b = (float2)(dc_floor_clamped(c.x + 0.5f), dc_floor_clamped(c.y + 0.5f));
        const float2 f = clamp((c - b) / r + 0.5f, 0.0f, 1.0f);
        const int i = (int)b.x, j = (int)b.y;
        return mix(mix(dc_texel(texels, t, i - 1, j - 1, slice), dc_texel(texels, t, i, j - 1, slice), f.x),
                   mix(dc_texel(texels, t, i - 1, j, slice), dc_texel(texels, t, i, j, slice), f.x), f.y);
    }
    const float2 lo = c - 0.5f * r, hi = c + 0.5f * r;
    const float2 first = (float2)(dc_floor_clamped(lo.x), dc_floor_clamped(lo.y)); /* lo >= -2 */
    float4 sum = (float4)(0.0f);
    for (int j = 0; j < 3; ++j) {
        const float wy = dc_box_share(lo.y, hi.y, first.y + (float)j) / r.y;
        if (!(wy > 0.0f)) continue;
        for (int i = 0; i < 3; ++i) {
            const float wx = dc_box_share(lo.x, hi.x, first.x + (float)i) / r.x;
            if (wx > 0.0f) sum += dc_texel(texels, t, (int)first.x + i, (int)first.y + j, slice) * (wx * wy);
        }
    }
    return sum;
}

inline float4 dc_sample_2d(__global const float4* texels, DcTexture t, float s, float tc, int filter) {
    return dc_sample_slice(texels, t, s, tc, 0, filter);
}

/* Volume lookup: nearest voxel, or trilinear between the two slices around r. */
inline float4 dc_sample_3d(__global const float4* texels, DcTexture t, float s, float tc, float r, int filter) {
    if (filter == DC_FILTER_NEAREST) return dc_sample_slice(texels, t, s, tc, dc_nearest_index(r, t.depth), filter);
    const float z = clamp(r * (float)t.depth - 0.5f, -1.0f, (float)t.depth);
    const float z0 = dc_floor_clamped(z);
    const int k = (int)z0;
    return mix(dc_sample_slice(texels, t, s, tc, k, filter), dc_sample_slice(texels, t, s, tc, k + 1, filter), z - z0);
}

/* The cube face of a direction (OpenGL rule; faces +X,-X,+Y,-Y,+Z,-Z; ties pick x, then y, then z). */
inline int dc_cube_face(float3 d) {
    const float3 a = fabs(d);
    if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0f ? 0 : 1;
    if (a.y >= a.z) return d.y >= 0.0f ? 2 : 3;
    return d.z >= 0.0f ? 4 : 5;
}

/* (s, t) of a direction on a given face (also for directions off that face, for footprints). */
inline float2 dc_cube_face_st(float3 d, int face) {
    float sc, tc, ma;
    switch (face) {
        case 0: sc = -d.z; tc = -d.y; ma = d.x; break;
        case 1: sc = d.z; tc = -d.y; ma = -d.x; break;
        case 2: sc = d.x; tc = d.z; ma = d.y; break;
        case 3: sc = d.x; tc = -d.z; ma = -d.y; break;
        case 4: sc = d.x; tc = -d.y; ma = d.z; break;
        default: sc = -d.x; tc = -d.y; ma = -d.z; break;
    }
    return (float2)(0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f));
}

/* The direction of face coordinates (sc, tc) in [-1, 1] (beyond on the extended face plane):
 * the inverse of dc_cube_face_st. */
inline float3 dc_cube_face_dir(int face, float sc, float tc) {
    switch (face) {
        case 0: return (float3)(1.0f, -tc, -sc);
        case 1: return (float3)(-1.0f, -tc, sc);
        case 2: return (float3)(sc, 1.0f, tc);
        case 3: return (float3)(sc, -1.0f, -tc);
        case 4: return (float3)(sc, -tc, 1.0f);
        default: return (float3)(-sc, -tc, -1.0f);
    }
}

/* Seamless cube taps (docs/conventions.md "Decals"): texel (i, j) of `face`, where a tap past one
 * edge takes the nearest texel of the face its centre's direction on the extended plane lands on,
 * and a tap past two edges (a cube corner) is the mean of the three texels meeting at that corner:
 * this face's corner texel and its two edge neighbours. */
inline float4 dc_cube_neighbour_texel(__global const float4* texels, DcTexture t, int face, int i, int j) {
    const float3 d = dc_cube_face_dir(face, (float)(2 * i + 1 - t.width) / (float)t.width,
                                      (float)(2 * j + 1 - t.height) / (float)t.height);
    const int f = dc_cube_face(d);
    const float2 st = dc_cube_face_st(d, f);
    return dc_texel(texels, t, dc_nearest_index(st.x, t.width), dc_nearest_index(st.y, t.height), f);
}

inline float4 dc_cube_tap(__global const float4* texels, DcTexture t, int face, int i, int j) {
    const bool in_i = i >= 0 && i < t.width, in_j = j >= 0 && j < t.height;
    if (in_i && in_j) return dc_texel(texels, t, i, j, face);
    if (in_i || in_j) return dc_cube_neighbour_texel(texels, t, face, i, j);
    const int ci = clamp(i, 0, t.width - 1), cj = clamp(j, 0, t.height - 1);
    return (dc_texel(texels, t, ci, cj, face) + dc_cube_neighbour_texel(texels, t, face, i, cj) +
            dc_cube_neighbour_texel(texels, t, face, ci, j)) *
           (1.0f / 3.0f);
}

/* A cube lookup at (s, tc) on `face`: nearest within the face, linear across the seams. */
inline float4 dc_sample_cube_face(__global const float4* texels, DcTexture t, float s, float tc, int face, int filter) {
    if (filter == DC_FILTER_NEAREST) return dc_sample_slice(texels, t, s, tc, face, filter);
#define DC_CUBE_TAP(a, b) dc_cube_tap(texels, t, face, (a), (b))
    DC_BILINEAR(DC_CUBE_TAP);
#undef DC_CUBE_TAP
}

inline float4 dc_sample_cube(__global const float4* texels, DcTexture t, float3 d, int filter) {
    const int face = dc_cube_face(d);
    const float2 st = dc_cube_face_st(d, face);
    return dc_sample_cube_face(texels, t, st.x, st.y, face, filter);
}

/* Mip level from texture coordinates at the pixel and where its right and lower neighbours'
 * rays meet the surface's tangent plane: log2 of the longer footprint axis in level-0 texels. */
inline float dc_lod(float2 st, float2 st_dx, float2 st_dy, DcTexture t) {
    const float2 size = (float2)((float)t.width, (float)t.height);
    /* (one square root of the larger squared length gave other bits on NVIDIA, whose length() is
     * not sqrt(dot), and ran 2 % slower there: docs/benchmarks.md stop 53) */
    const float rho = fmax(length((st_dx - st) * size), length((st_dy - st) * size));
    return rho > 1.0f ? log2(rho) : 0.0f;
}

/* The same for a volume, from decal-local points: (s, t, r) = (x + 0.5, 0.5 - y, z + 0.5) moves
 * with local space up to a sign, so the footprint in level-0 voxels is the local one scaled. */
inline float dc_lod_volume(float3 l, float3 l_dx, float3 l_dy, DcTexture t) {
    const float3 size = (float3)((float)t.width, (float)t.height, (float)t.depth);
    const float rho = fmax(length((l_dx - l) * size), length((l_dy - l) * size));
    return rho > 1.0f ? log2(rho) : 0.0f;
}

/* How one mip level is filtered: bilinear in a slice, seamless bilinear on a cube face, or
 * trilinear in a volume level. */
#define DC_LEVEL_SLICE 0
#define DC_LEVEL_CUBE 1
#define DC_LEVEL_VOLUME 2

DC_CPU_INLINE float4 dc_sample_level(__global const float4* texels, DcTexture t, float s, float tc, float r, int slice,
                                     int how) {
    if (how == DC_LEVEL_VOLUME) return dc_sample_3d(texels, t, s, tc, r, DC_FILTER_LINEAR);
    if (how == DC_LEVEL_CUBE) return dc_sample_cube_face(texels, t, s, tc, slice, DC_FILTER_LINEAR);
    return dc_sample_slice(texels, t, s, tc, slice, DC_FILTER_LINEAR);
}

/* Mip lookup: the two levels around lod, each filtered `how`, blended (quadrilinear for volumes). */
DC_CPU_INLINE float4 dc_sample_chain(__global const float4* texels, __global const DcTexture* textures, int index,
                                     float s, float tc, float r, int slice, float lod, int how) {
    const int levels = textures[index].levels;
    lod = clamp(lod, 0.0f, (float)(levels - 1));
    const int l0 = (int)dc_floor_clamped(lod);
    const int l1 = min(l0 + 1, levels - 1);
    const float4 a = dc_sample_level(texels, textures[index + l0], s, tc, r, slice, how);
    const float f = lod - (float)l0;
    if (!(f > 0.0f)) return a;
    return mix(a, dc_sample_level(texels, textures[index + l1], s, tc, r, slice, how), f);
}

/* Trilinear mip lookup in one slice of a 2D texture. */
inline float4 dc_sample_mip(__global const float4* texels, __global const DcTexture* textures, int index, float s,
                            float tc, int slice, float lod) {
    return dc_sample_chain(texels, textures, index, s, tc, 0.0f, slice, lod, DC_LEVEL_SLICE);
}

#undef DC_BILINEAR

#endif
