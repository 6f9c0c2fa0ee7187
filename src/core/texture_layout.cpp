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
    for (const Texture2D& f : faces) {
        if (f.width != cube.width || f.height != cube.width || f.depth != 1)
            throw inputError(fmt::format("{}: cube faces must be square and all the same size ({}x{} here, {}x{} first)",
                                         f.source, f.width, f.height, cube.width, cube.width));
        cube.texels.insert(cube.texels.end(), f.texels.begin(), f.texels.end());
    }
    return cube;
}

std::vector<Texture2D> mipChain(const Texture2D& texture) {
    std::vector<Texture2D> chain{texture};
    while (chain.back().width > 1 || chain.back().height > 1) {
        const Texture2D& above = chain.back();
        Texture2D level;
        level.source = above.source;
        level.width = std::max(1, above.width / 2);
        level.height = std::max(1, above.height / 2);
        level.depth = above.depth;
        level.texels.resize(std::size_t(level.width) * level.height * level.depth);
        auto at = [&](int i, int j, int k) {
            i = std::min(i, above.width - 1);
            j = std::min(j, above.height - 1);
            return above.texels[(std::size_t(k) * above.height + j) * above.width + i];
        };
        for (int k = 0; k < level.depth; ++k)
            for (int j = 0; j < level.height; ++j)
                for (int i = 0; i < level.width; ++i)
                    level.texels[(std::size_t(k) * level.height + j) * level.width + i] =
                        0.25f * (at(2 * i, 2 * j, k) + at(2 * i + 1, 2 * j, k) + at(2 * i, 2 * j + 1, k) +
                                 at(2 * i + 1, 2 * j + 1, k));
        chain.push_back(std::move(level));
    }
    return chain;
}

}  // namespace decalcomp
