// Texture decoding: the input as a PNG or EXR decal texture (by its magic number; other formats
// are OpenImageIO's plugins, not decalcomp's code), then the layouts and mip chain a scene builds
// from it. The alpha mode and content kind vary with the input's length, so no seed needs a prefix.
#include <cstring>

#include "decalcomp/decal.hpp"
#include "decalcomp/textures.hpp"
#include "fuzz/fuzz_support.hpp"
#include "fuzz/fuzz_targets.hpp"

namespace decalcomp::fuzz {

namespace {

const char* extensionFor(const std::uint8_t* data, std::size_t size) {
    static const std::uint8_t png[] = {0x89, 'P', 'N', 'G'};
    static const std::uint8_t exr[] = {0x76, 0x2f, 0x31, 0x01};
    if (size >= 4 && std::memcmp(data, png, 4) == 0) return ".png";
    if (size >= 4 && std::memcmp(data, exr, 4) == 0) return ".exr";
    return nullptr;
}

}  // namespace

void fuzzTexture(const std::uint8_t* data, std::size_t size) {
    const char* extension = extensionFor(data, size);
    if (!extension) return;
    const std::string path = writeScratchFile(std::string("texture") + extension, asText(data, size));
    const AlphaMode alpha = AlphaMode(size % 3);
    const TextureContent content = size / 3 % 2 ? TextureContent::Data : TextureContent::Colour;
    Texture2D texture;
    if (!inputErrorsAllowed([&] { texture = loadTexture2D(path, alpha, content); })) return;
    inputErrorsAllowed([&] { (void)mipChain(volumeFromStrip(texture)); });
    inputErrorsAllowed([&] { (void)mipChain(cubeFromStrip(texture)); });
    inputErrorsAllowed([&] { (void)mipChain(texture); });
}

}  // namespace decalcomp::fuzz
