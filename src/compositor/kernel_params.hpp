#pragma once
// Host-side preparation of the plain structs the kernels read (double math, stored as float).
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"
#include "shared_types.h"

namespace decalcomp {

cl_types::DcFrame makeFrameParams(const GBuffer& frame, const Camera& camera, int decal_count);
std::vector<cl_types::DcDecal> makeDecalParams(const DecalScene& scene, const Camera& camera);

struct PackedTextures {
    std::vector<cl_types::DcTexture> table;
    std::vector<float> texels;  // RGBA float4 per texel, all textures back to back
};
PackedTextures packTextures(const std::vector<Texture2D>& textures);

int tileCount(int pixels);  // tiles needed to cover `pixels`

}  // namespace decalcomp
