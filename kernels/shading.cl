/* Shading: per pixel, the camera-space point, then the tile's decals in order, each blended
 * into the albedo (DESIGN.md section 3). Background pixels are copied through unchanged. */
#include "shared_types.h"
#include "matrix.h"
#include "reconstruct.h"
#include "texture_sample.h"
#include "decal_kinds.h"
#include "occlusion.h"

__kernel void dc_shade(__constant const DcFrame* frame, __read_only image2d_t depth_image,
                       __read_only image2d_t position_image, __read_only image2d_t normal_image,
                       __read_only image2d_t albedo_in, __global float4* albedo_out,
                       __global const DcDecal* decals, __global const DcTexture* textures,
                       __global const float4* texels, __global const int* tile_offsets,
                       __global const int* tile_decals, int binned, __global const float* mask_weights,
                       __global const uint* occlusion_maps) {
    const int x = get_global_id(0), y = get_global_id(1);
    if (x >= frame->width || y >= frame->height) return;
    float4 albedo = read_imagef(albedo_in, dc_pixel_sampler, (int2)(x, y));
    float3 p;
    if (dc_reconstruct(frame, depth_image, position_image, x, y, &p)) {
        float3 normal = (float3)(0.0f);
        if (frame->reconstruct_normals) {
            normal = dc_normal_from_depth(frame, depth_image, position_image, x, y, p);
        } else if (frame->has_normal) {
            const float3 n = read_imagef(normal_image, dc_pixel_sampler, (int2)(x, y)).xyz;
            normal = (float3)(dot(vload3(0, frame->world_to_camera), n), dot(vload3(0, frame->world_to_camera + 4), n),
                              dot(vload3(0, frame->world_to_camera + 8), n));
            normal = normalize(normal);
        }
        float3 p_dx = p, p_dy = p;
        const int footprint = (frame->has_normal || frame->reconstruct_normals) &&
                              dc_footprint(frame, x, y, p, normal, &p_dx, &p_dy);
        int begin = 0, end = frame->decal_count;
        if (binned) {
            const int tile = (y / DC_TILE_SIZE) * frame->tiles_x + x / DC_TILE_SIZE;
            begin = tile_offsets[tile];
            end = tile_offsets[tile + 1];
        }
        for (int k = begin; k < end; ++k) {
            __global const DcDecal* d = &decals[binned ? tile_decals[k] : k];
            /* blast occlusion: a surface nearer the origin hides this one from the blast */
            if (d->occlusion_map >= 0 && !dc_blast_reaches(d, occlusion_maps, p, normal)) continue;
            const float4 colour =
                dc_decal_colour(d, textures, texels, p, normal, frame->has_normal || frame->reconstruct_normals, p_dx,
                                p_dy, footprint);
            if (!(colour.w > 0.0f)) continue;
            float weight = d->opacity;
            if (d->mask >= 0) weight *= mask_weights[(size_t)d->mask * frame->width * frame->height + y * frame->width + x];
            /* premultiplied colour: straight colour * f == colour.rgb * weight */
            const float f = clamp(colour.w * weight, 0.0f, 1.0f);
            albedo.xyz = albedo.xyz * (1.0f - f) + colour.xyz * weight;
        }
    }
    albedo_out[y * frame->width + x] = albedo;
}
