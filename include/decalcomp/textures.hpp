#pragma once
// Decal texture decoding through OpenImageIO.
#include <string>

#include "decalcomp/decal.hpp"

namespace decalcomp {

struct TextureColour;  // textures/colour_config.hpp

enum class AlphaMode { Auto, Straight, Premultiplied };
// Colour images (albedo, emission) are sRGB-encoded when stored as integers; data images (normal
// maps, ORM) hold their values as they are.
enum class TextureContent { Colour, Data };

// Loads an image as linear, premultiplied RGBA float. 8/16-bit integer files (PNG, TGA...) are
// sRGB-encoded with straight alpha; float files (EXR) are linear and premultiplied unless
// `alpha` says Straight. Grey and RGB images get alpha 1. Data content skips the sRGB decode.
// With `colour`, colour content is instead converted by OpenColorIO from its colour space to the
// working space (straight alpha while converting). Throws Error(Input) naming the file.
Texture2D loadTexture2D(const std::string& path, AlphaMode alpha = AlphaMode::Auto,
                        TextureContent content = TextureContent::Colour, const TextureColour* colour = nullptr);

float srgbToLinear(float encoded);
float linearToSrgb(float linear);
// A linear value as an 8-bit sRGB code for display (previews, contact sheets, baked PNGs): clamped
// to [0, 1], non-finite values as 0, rounded to nearest.
unsigned char linearToSrgbByte(float linear);

}  // namespace decalcomp
