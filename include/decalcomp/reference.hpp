#pragma once
// The scalar C++ reference of tile bounds, binning and shading: double precision, brute force,
// written from the conventions (docs/conventions.md) and not from the kernels. Tests compare the
// OpenCL kernels with it.
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp::reference {

// World-space point seen by data-window pixel (x, y), or nullopt for background.
std::optional<glm::dvec3> pixelWorldPoint(const GBuffer& frame, const Camera& camera, int x, int y);

struct DepthRange {
    double min = 0, max = 0;
    bool empty = true;
};
// Planar view depth range of each tile_size x tile_size tile, row-major over tiles.
std::vector<DepthRange> tileDepthRanges(const GBuffer& frame, const Camera& camera, int tile_size);

// Exact bins: decal d is listed for tile t iff some pixel of t lies inside d (in scene order).
std::vector<std::vector<int>> exactBins(const GBuffer& frame, const Camera& camera, const DecalScene& scene,
                                        int tile_size);

// Filtered texture lookup with (s, t) as in docs/conventions.md; premultiplied RGBA.
glm::dvec4 sampleTexture(const Texture2D& texture, double s, double t, TextureFilter filter);

struct ShadeResult {
    Plane albedo;
    // 1 where float rounding may legitimately flip the result: the point lies within `margin`
    // of a decal's box face, or a nearest lookup lies within `margin` of a texel edge.
    std::vector<std::uint8_t> ambiguous;
};
// Brute force: every pixel tests every decal in scene order.
ShadeResult shade(const GBuffer& frame, const Camera& camera, const DecalScene& scene,
                  double margin = 2e-5);

}  // namespace decalcomp::reference
