#pragma once
// Host-side preparation of the plain structs the kernels read (double math, stored as float).
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"
#include "shared_types.h"

namespace decalcomp {

cl_types::DcFrame makeFrameParams(const GBuffer& frame, const Camera& camera, int decal_count);
// `texture_entries` maps scene texture indices to texture table entries (PackedTextures).
std::vector<cl_types::DcDecal> makeDecalParams(const DecalScene& scene, const Camera& camera,
                                               const std::vector<int>& texture_entries);

struct PackedTextures {
    std::vector<cl_types::DcTexture> table;  // each texture's mip levels in consecutive entries
    std::vector<int> first_entry;            // table entry of each scene texture's level 0
    std::vector<float> texels;               // RGBA float4 per texel, all levels back to back
};
PackedTextures packTextures(const std::vector<Texture2D>& textures);

int tileCount(int pixels);  // tiles needed to cover `pixels`

}  // namespace decalcomp
