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

inline float4 dc_sample_cube(__global const float4* texels, DcTexture t, float3 d, int filter) {
    const int face = dc_cube_face(d);
    const float2 st = dc_cube_face_st(d, face);
    return dc_sample_slice(texels, t, st.x, st.y, face, filter);
}

/* Mip level from texture coordinates at the pixel and where its right and lower neighbours'
 * rays meet the surface's tangent plane: log2 of the longer footprint axis in level-0 texels. */
inline float dc_lod(float2 st, float2 st_dx, float2 st_dy, DcTexture t) {
    const float2 size = (float2)((float)t.width, (float)t.height);
    const float rho = fmax(length((st_dx - st) * size), length((st_dy - st) * size));
    return rho > 1.0f ? log2(rho) : 0.0f;
}

/* Trilinear mip lookup in one slice: bilinear in the two levels around lod, blended. */
inline float4 dc_sample_mip(__global const float4* texels, __global const DcTexture* textures, int index, float s,
                            float tc, int slice, float lod) {
    const int levels = textures[index].levels;
    lod = clamp(lod, 0.0f, (float)(levels - 1));
    const int l0 = (int)floor(lod);
    const int l1 = min(l0 + 1, levels - 1);
    const float4 a = dc_sample_slice(texels, textures[index + l0], s, tc, slice, DC_FILTER_LINEAR);
    const float f = lod - (float)l0;
    if (!(f > 0.0f)) return a;
    return mix(a, dc_sample_slice(texels, textures[index + l1], s, tc, slice, DC_FILTER_LINEAR), f);
}

#endif
