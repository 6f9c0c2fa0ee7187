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

// Whether a decal-local point lies inside the decal's volume (per kind).
bool insideDecal(const Decal& decal, const glm::dvec3& local);

// Exact bins: decal d is listed for tile t iff some pixel of t lies inside d (in scene order).
std::vector<std::vector<int>> exactBins(const GBuffer& frame, const Camera& camera, const DecalScene& scene,
                                        int tile_size);

// Filtered texture lookups as in docs/conventions.md; premultiplied RGBA.
glm::dvec4 sampleTexture(const Texture2D& texture, double s, double t, TextureFilter filter);
glm::dvec4 sampleVolume(const Texture2D& texture, double s, double t, double r, TextureFilter filter);
glm::dvec4 sampleCube(const Texture2D& texture, const glm::dvec3& direction, TextureFilter filter);

// The OpenGL cube-map rule: face (+X,-X,+Y,-Y,+Z,-Z = 0..5) and (s, t) of a direction.
struct CubeLookup {
    int face = 0;
    double s = 0, t = 0;
};
CubeLookup cubeLookup(const glm::dvec3& direction);

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
