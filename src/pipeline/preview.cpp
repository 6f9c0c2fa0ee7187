// PNG preview, sRGB-encoded for viewing: the input albedo beside the composited albedo and, when
// the frames have a normal plane, a second row with a simple lit view of each, so a person can see
// what a normal-mapped decal did (the albedo row alone does not show the normals), and, when the
// beauty was rebuilt, a last row with the beauty before and after, tone-mapped for display.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/glm.hpp>

#include "decalcomp/error.hpp"
#include "decalcomp/geometry.hpp"
#include "decalcomp/normal_codec.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/textures.hpp"
#include "images/image_codecs.hpp"

namespace decalcomp {

void writePreview(const GBuffer& before, const GBuffer& after, const Camera& camera, const std::string& path,
                  const Plane* beauty_before, const Plane* beauty_after) {
    const int w = before.width, h = before.height, gap = 4;
    const bool lit = before.has(Attribute::Normal) && after.has(Attribute::Normal);
    const bool beauty = beauty_before && beauty_after;
    const int rows = 1 + (lit ? 1 : 0) + (beauty ? 1 : 0);
    const int out_w = 2 * w + gap, out_h = rows * h + (rows - 1) * gap;
    std::vector<unsigned char> pixels(std::size_t(out_w) * out_h * 3, 0);
    auto store = [&](int x, int y, int c, float v) {
        pixels[(std::size_t(y) * out_w + x) * 3 + c] = linearToSrgbByte(v);
    };
    // Lambert with a fixed light from the upper left, in front of the scene, in camera space (-Z
    // forward, +Y up), so it reads the same for any scene.
    const glm::vec3 light = glm::normalize(glm::vec3(-1.0f, 1.0f, 1.0f));
    const float ambient = 0.2f;
    auto put = [&](const GBuffer& g, int x_offset) {
        const Plane& albedo = g.planes.at(Attribute::Albedo);
        const Plane* normal = lit ? &g.planes.at(Attribute::Normal) : nullptr;
        const NormalCodec normals(g.normal_encoding, camera);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t p = std::size_t(y) * w + x;
                glm::vec3 a(0.0f);
                for (int c = 0; c < std::min(3, albedo.components); ++c) a[c] = albedo.at(p, c);
                for (int c = 0; c < 3; ++c) store(x + x_offset, y, c, a[c]);
                if (!normal || !isGeometryPixel(g, p)) continue;  // background stays black
                const glm::vec3 n =
                    normals.worldToCamera(normals.toWorld({normal->at(p, 0), normal->at(p, 1), normal->at(p, 2)}));
                const float len = glm::length(n);
                const float shade = len > 0.0f ? ambient + (1.0f - ambient) * std::max(0.0f, glm::dot(n / len, light))
                                               : 0.0f;
                for (int c = 0; c < 3; ++c) store(x + x_offset, y + h + gap, c, a[c] * shade);
            }
    };
    put(before, 0);
    put(after, w + gap);
    // The beauty is scene-linear and may exceed 1: Reinhard (x / (1 + x)) keeps highlights apart.
    auto putBeauty = [&](const Plane& plane, int x_offset) {
        const int y_offset = (rows - 1) * (h + gap);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) {
                    const float v = std::max(plane.at(std::size_t(y) * w + x, c), 0.0f);
                    store(x + x_offset, y + y_offset, c, v / (1.0f + v));
                }
    };
    if (beauty) {
        putBeauty(*beauty_before, 0);
        putBeauty(*beauty_after, w + gap);
    }
    const images::Codecs& codecs = images::imageCodecs(ErrorKind::Output, path);
    if (const std::string failure = codecs.write(path, images::png8(out_w, out_h, 3, pixels.data()));
        !failure.empty()) {
        std::error_code ec;
        std::filesystem::remove(path, ec);
        throw outputError(fmt::format("{}: cannot write preview PNG: {}", path, failure));
    }
}

}  // namespace decalcomp
