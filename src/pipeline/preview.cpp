// PNG preview: the input albedo beside the composited albedo, sRGB-encoded for viewing.
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "decalcomp/error.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/textures.hpp"

namespace decalcomp {

void writeAlbedoPreview(const GBuffer& before, const GBuffer& after, const std::string& path) {
    const int w = before.width, h = before.height, gap = 4;
    const int out_w = 2 * w + gap;
    std::vector<unsigned char> pixels(std::size_t(out_w) * h * 3, 0);
    auto put = [&](const GBuffer& g, int x_offset) {
        const Plane& albedo = g.planes.at(Attribute::Albedo);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) {
                    const float v = c < albedo.components ? albedo.at(std::size_t(y) * w + x, c) : 0.0f;
                    const float encoded = linearToSrgb(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f));
                    pixels[(std::size_t(y) * out_w + x + x_offset) * 3 + c] = (unsigned char)(encoded * 255.0f + 0.5f);
                }
    };
    put(before, 0);
    put(after, w + gap);
    auto out = OIIO::ImageOutput::create("png");
    OIIO::ImageSpec spec(out_w, h, 3, OIIO::TypeDesc::UINT8);
    if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close()) {
        std::error_code ec;
        std::filesystem::remove(path, ec);
        throw outputError(fmt::format("{}: cannot write preview PNG: {}", path, out ? out->geterror() : OIIO::geterror()));
    }
}

}  // namespace decalcomp
