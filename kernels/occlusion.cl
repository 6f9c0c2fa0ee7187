/* Blast occlusion maps (docs/conventions.md "Blast occlusion"): every G-buffer point, for every
 * occluding decal, writes its distance from the decal's origin into its map texel with
 * atomic_min. The host fills the maps with +inf bits first. */
#include "shared_types.h"
#include "matrix.h"
#include "reconstruct.h"
#include "texture_sample.h"
#include "decal_kinds.h"
#include "occlusion.h"

/* A shading program (ComputeDevice::shadingProgram) holds its dc_shade alone. */
#ifndef DC_SHADING_PROGRAM

__kernel void dc_occlusion_build(__constant const DcFrame* frame, __global const float* depth_plane,
                                 __global const float4* position_plane, __global const DcDecal* decals,
                                 __global const int* occluders, int occluder_count, __global uint* maps) {
    const int x = get_global_id(0), y = get_global_id(1);
    if (x >= frame->width || y >= frame->height) return;
    float3 p;
    if (!dc_reconstruct(frame, depth_plane, position_plane, x, y, &p)) return;
    for (int k = 0; k < occluder_count; ++k) {
        __global const DcDecal* d = &decals[occluders[k]];
        const float3 l = dc_affine_global(d->camera_to_local, p);
        DcMapTexel t;
        if (dc_occlusion_texel(d, l, &t)) atomic_min(&maps[dc_occlusion_index(d, t)], as_uint(length(l)));
    }
}

#endif /* DC_SHADING_PROGRAM */
