/* Shading: per pixel, the camera-space point, then the tile's decals in order, each blended
 * into the albedo (DESIGN.md section 3). Background pixels are copied through unchanged. */
#include "shared_types.h"
#include "matrix.h"
#include "reconstruct.h"
#include "texture_sample.h"

__kernel void dc_shade(__constant const DcFrame* frame, __read_only image2d_t depth_image,
                       __read_only image2d_t position_image, __read_only image2d_t albedo_in,
                       __global float4* albedo_out, __global const DcDecal* decals,
                       __global const DcTexture* textures, __global const float4* texels,
                       __global const int* tile_offsets, __global const int* tile_decals, int binned,
                       __global const float* mask_weights) {
    const int x = get_global_id(0), y = get_global_id(1);
    if (x >= frame->width || y >= frame->height) return;
    float4 albedo = read_imagef(albedo_in, dc_pixel_sampler, (int2)(x, y));
    float3 p;
    if (dc_reconstruct(frame, depth_image, position_image, x, y, &p)) {
        int begin = 0, end = frame->decal_count;
        if (binned) {
            const int tile = (y / DC_TILE_SIZE) * frame->tiles_x + x / DC_TILE_SIZE;
            begin = tile_offsets[tile];
            end = tile_offsets[tile + 1];
        }
        for (int k = begin; k < end; ++k) {
            __global const DcDecal* d = &decals[binned ? tile_decals[k] : k];
            const float3 local_point = dc_affine_global(d->camera_to_local, p);
            if (!(fabs(local_point.x) <= 0.5f && fabs(local_point.y) <= 0.5f && fabs(local_point.z) <= 0.5f)) continue;
            if (d->texture < 0) continue;
            const float4 texel =
                dc_sample_2d(texels, textures[d->texture], local_point.x + 0.5f, 0.5f - local_point.y, d->filter);
            /* premultiplied texel: colour * f == texel.rgb * opacity */
            float weight = d->opacity;
            if (d->mask >= 0) weight *= mask_weights[(size_t)d->mask * frame->width * frame->height + y * frame->width + x];
            const float f = clamp(texel.w * weight, 0.0f, 1.0f);
            albedo.xyz = albedo.xyz * (1.0f - f) + texel.xyz * weight;
        }
    }
    albedo_out[y * frame->width + x] = albedo;
}
