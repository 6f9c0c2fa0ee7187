// Re-slicing decoded images into volumes and cube maps (Texture2D with depth > 1).
#include <fmt/format.h>

#include <algorithm>

#include "decalcomp/decal.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

Texture2D volumeFromStrip(Texture2D strip) {
    if (strip.width <= 0 || strip.depth != 1 || strip.height % strip.width != 0)
        throw inputError(fmt::format("{}: a volume strip must be W wide and a multiple of W high (is {}x{})",
                                     strip.source, strip.width, strip.height));
    // Slices of a vertical strip are already contiguous, top slice first.
    strip.depth = strip.height / strip.width;
    strip.height = strip.width;
    strip.shape = TextureShape::Volume;
    return strip;
}

Texture2D cubeFromStrip(const Texture2D& strip) {
    if (strip.depth != 1 || strip.width != 6 * strip.height || strip.height <= 0)
        throw inputError(fmt::format("{}: a cube strip must be six square faces side by side (is {}x{})", strip.source,
                                     strip.width, strip.height));
    const int n = strip.height;
    Texture2D cube;
    cube.source = strip.source;
    cube.width = cube.height = n;
    cube.depth = 6;
    cube.shape = TextureShape::Cube;
    cube.texels.reserve(std::size_t(6) * n * n);
    for (int face = 0; face < 6; ++face)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) cube.texels.push_back(strip.texels[std::size_t(j) * strip.width + face * n + i]);
    return cube;
}

Texture2D cubeFromFaces(const std::vector<Texture2D>& faces) {
    if (faces.size() != 6) throw inputError(fmt::format("a cube needs 6 faces, got {}", faces.size()));
    Texture2D cube;
    cube.source = faces[0].source;
    cube.width = cube.height = faces[0].width;
    cube.depth = 6;
    cube.shape = TextureShape::Cube;
    for (const Texture2D& f : faces) {
        if (f.width != cube.width || f.height != cube.width || f.depth != 1)
            throw inputError(fmt::format("{}: cube faces must be square and all the same size ({}x{} here, {}x{} first)",
                                         f.source, f.width, f.height, cube.width, cube.width));
        cube.texels.insert(cube.texels.end(), f.texels.begin(), f.texels.end());
    }
    return cube;
}

namespace {

// One axis of a mip step from n texels to m = max(1, n / 2): output texel o covers the input
// interval [o n / m, (o + 1) n / m); each input texel it overlaps gets the overlap's share.
struct AxisTap {
    int index;
    float weight;
};
std::vector<std::vector<AxisTap>> axisTaps(int n, int m) {
    std::vector<std::vector<AxisTap>> taps(static_cast<std::size_t>(m));
    for (int o = 0; o < m; ++o) {
        // in units of 1/m input texels: the output covers [o n, (o + 1) n), input k covers [k m, (k + 1) m)
        const long begin = long(o) * n, end = long(o + 1) * n;
        for (int k = int(begin / m); k < n && long(k) * m < end; ++k) {
            const long overlap = std::min(end, long(k + 1) * m) - std::max(begin, long(k) * m);
            if (overlap > 0) taps[std::size_t(o)].push_back({k, float(double(overlap) / double(n))});
        }
    }
    return taps;
}

}  // namespace

std::vector<Texture2D> mipChain(const Texture2D& texture) {
    const bool volume = texture.shape == TextureShape::Volume;
    std::vector<Texture2D> chain{texture};
    while (chain.back().width > 1 || chain.back().height > 1 || (volume && chain.back().depth > 1)) {
        const Texture2D& above = chain.back();
        Texture2D level;
        level.source = above.source;
        level.shape = above.shape;
        level.width = std::max(1, above.width / 2);
        level.height = std::max(1, above.height / 2);
        level.depth = volume ? std::max(1, above.depth / 2) : above.depth;
        const auto tap_i = axisTaps(above.width, level.width), tap_j = axisTaps(above.height, level.height);
        // flat and cube slices map one to one
        const auto tap_k = volume ? axisTaps(above.depth, level.depth) : axisTaps(1, 1);
        level.texels.resize(std::size_t(level.width) * level.height * level.depth);
        for (int k = 0; k < level.depth; ++k)
            for (int j = 0; j < level.height; ++j)
                for (int i = 0; i < level.width; ++i) {
                    glm::vec4 sum(0.0f);
                    for (const AxisTap& tk : tap_k[std::size_t(volume ? k : 0)]) {
                        const std::size_t slice = std::size_t(volume ? tk.index : k);
                        for (const AxisTap& tj : tap_j[std::size_t(j)]) {
                            const std::size_t row =
                                (slice * std::size_t(above.height) + std::size_t(tj.index)) * std::size_t(above.width);
                            for (const AxisTap& ti : tap_i[std::size_t(i)])
                                sum += (tk.weight * tj.weight * ti.weight) * above.texels[row + std::size_t(ti.index)];
                        }
                    }
                    level.texels[(std::size_t(k) * level.height + j) * level.width + i] = sum;
                }
        chain.push_back(std::move(level));
    }
    return chain;
}

}  // namespace decalcomp
