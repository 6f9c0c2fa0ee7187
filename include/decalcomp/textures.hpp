#pragma once
// Decal texture decoding through OpenImageIO.
#include <string>

#include "decalcomp/decal.hpp"

namespace decalcomp {

enum class AlphaMode { Auto, Straight, Premultiplied };

// Loads an image as linear, premultiplied RGBA float. 8/16-bit integer files (PNG, TGA...) are
// sRGB-encoded with straight alpha; float files (EXR) are linear and premultiplied unless
// `alpha` says Straight. Grey and RGB images get alpha 1. Throws Error(Input) naming the file.
Texture2D loadTexture2D(const std::string& path, AlphaMode alpha = AlphaMode::Auto);

float srgbToLinear(float encoded);
float linearToSrgb(float linear);

}  // namespace decalcomp
