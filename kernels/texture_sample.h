/* 2D texture lookups in the packed texel buffer: clamp-to-edge addressing, texel centres at
 * (i + 0.5) / width, t = 0 on the image's top row. */
#ifndef DECALCOMP_TEXTURE_SAMPLE_H
#define DECALCOMP_TEXTURE_SAMPLE_H

inline float4 dc_texel(__global const float4* texels, DcTexture t, int i, int j) {
    i = clamp(i, 0, t.width - 1);
    j = clamp(j, 0, t.height - 1);
    return texels[t.offset + j * t.width + i];
}

inline float4 dc_sample_2d(__global const float4* texels, DcTexture t, float s, float tc, int filter) {
    if (filter == DC_FILTER_NEAREST) {
        /* clamp in float first so huge coordinates cannot overflow the int conversion */
        const float x = clamp(floor(s * (float)t.width), -1.0f, (float)t.width);
        const float y = clamp(floor(tc * (float)t.height), -1.0f, (float)t.height);
        return dc_texel(texels, t, (int)x, (int)y);
    }
    const float x = clamp(s * (float)t.width - 0.5f, -1.0f, (float)t.width);
    const float y = clamp(tc * (float)t.height - 0.5f, -1.0f, (float)t.height);
    const float x0 = floor(x), y0 = floor(y);
    const float fx = x - x0, fy = y - y0;
    const int i = (int)x0, j = (int)y0;
    const float4 top = mix(dc_texel(texels, t, i, j), dc_texel(texels, t, i + 1, j), fx);
    const float4 bottom = mix(dc_texel(texels, t, i, j + 1), dc_texel(texels, t, i + 1, j + 1), fx);
    return mix(top, bottom, fy);
}

#endif
