/* Texture lookups in the packed texel buffer: clamp-to-edge addressing, texel centres at
 * (i + 0.5) / width, t = 0 on the image's top row. A texture has `depth` slices of
 * width x height texels: 1 for 2D images, D for volumes, 6 for cube faces. */
#ifndef DECALCOMP_TEXTURE_SAMPLE_H
#define DECALCOMP_TEXTURE_SAMPLE_H

inline float4 dc_texel(__global const float4* texels, DcTexture t, int i, int j, int slice) {
    i = clamp(i, 0, t.width - 1);
    j = clamp(j, 0, t.height - 1);
    slice = clamp(slice, 0, t.depth - 1);
    return texels[t.offset + (slice * t.height + j) * t.width + i];
}

/* Texel index along one axis for nearest lookup; clamped in float so huge inputs cannot overflow. */
inline int dc_nearest_index(float coord, int size) {
    return (int)clamp(floor(coord * (float)size), -1.0f, (float)size);
}

/* 2D lookup within one slice. */
inline float4 dc_sample_slice(__global const float4* texels, DcTexture t, float s, float tc, int slice, int filter) {
    if (filter == DC_FILTER_NEAREST)
        return dc_texel(texels, t, dc_nearest_index(s, t.width), dc_nearest_index(tc, t.height), slice);
    const float x = clamp(s * (float)t.width - 0.5f, -1.0f, (float)t.width);
    const float y = clamp(tc * (float)t.height - 0.5f, -1.0f, (float)t.height);
    const float x0 = floor(x), y0 = floor(y);
    const float fx = x - x0, fy = y - y0;
    const int i = (int)x0, j = (int)y0;
    const float4 top = mix(dc_texel(texels, t, i, j, slice), dc_texel(texels, t, i + 1, j, slice), fx);
    const float4 bottom = mix(dc_texel(texels, t, i, j + 1, slice), dc_texel(texels, t, i + 1, j + 1, slice), fx);
    return mix(top, bottom, fy);
}

inline float4 dc_sample_2d(__global const float4* texels, DcTexture t, float s, float tc, int filter) {
    return dc_sample_slice(texels, t, s, tc, 0, filter);
}

/* Volume lookup: nearest voxel, or trilinear between the two slices around r. */
inline float4 dc_sample_3d(__global const float4* texels, DcTexture t, float s, float tc, float r, int filter) {
    if (filter == DC_FILTER_NEAREST) return dc_sample_slice(texels, t, s, tc, dc_nearest_index(r, t.depth), filter);
    const float z = clamp(r * (float)t.depth - 0.5f, -1.0f, (float)t.depth);
    const float z0 = floor(z);
    const int k = (int)z0;
    return mix(dc_sample_slice(texels, t, s, tc, k, filter), dc_sample_slice(texels, t, s, tc, k + 1, filter), z - z0);
}

/* Cube lookup by direction (OpenGL rule; faces +X,-X,+Y,-Y,+Z,-Z; ties pick x, then y, then z). */
inline float4 dc_sample_cube(__global const float4* texels, DcTexture t, float3 d, int filter) {
    const float3 a = fabs(d);
    int face;
    float sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0.0f ? 0 : 1;
        ma = a.x;
        sc = d.x >= 0.0f ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y >= 0.0f ? 2 : 3;
        ma = a.y;
        sc = d.x;
        tc = d.y >= 0.0f ? d.z : -d.z;
    } else {
        face = d.z >= 0.0f ? 4 : 5;
        ma = a.z;
        sc = d.z >= 0.0f ? d.x : -d.x;
        tc = -d.y;
    }
    return dc_sample_slice(texels, t, 0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f), face, filter);
}

#endif
