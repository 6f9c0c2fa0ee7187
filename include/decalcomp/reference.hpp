#pragma once
// The scalar C++ reference of tile bounds, binning and shading: double precision, brute force,
// written from the conventions (docs/conventions.md) and not from the kernels. Tests compare the
// OpenCL kernels with it.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/beauty.hpp"
#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp::reference {

// Camera-space point seen by data-window pixel (x, y), or nullopt for background.
std::optional<glm::dvec3> pixelCameraPoint(const GBuffer& frame, const Camera& camera, int x, int y);
// The same point in world space.
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

// ---- Materials (docs/conventions.md "Materials"), in world space.

// A pixel's material while decals are applied.
struct Surface {
    glm::dvec3 albedo{0.0}, normal{0.0}, emission{0.0};  // normal: world-space unit vector
    double roughness = 0.0, metallic = 0.0, ao = 0.0;
    bool normal_changed = false;
};
Surface surfaceAt(const std::map<Attribute, Plane>& planes, std::size_t pixel);  // normal left 0
void storeSurface(const Surface& surface, std::size_t pixel, std::map<Attribute, Plane>& planes);  // all but the normal
// sum += w * s, field by field (a pixel filter's taps); normal_changed is or-ed.
void addWeighted(Surface& sum, const Surface& s, double w);

// What a decal offers at one point: its textures' premultiplied texels (nullopt = no such
// texture) and the world directions of its frame.
struct DecalValues {
    std::optional<glm::dvec4> albedo, normal, orm, emission;
    glm::dvec3 facing{0.0}, right{0.0}, up{0.0};
};

// One target's blend: a with value v at strength g (f = clamp(g, 0, 1)).
double blend(double a, double v, double g, BlendOp op);
glm::dvec3 blend(const glm::dvec3& a, const glm::dvec3& v, double g, BlendOp op);
// Base and detail normals in a tangent frame (z = the frame's normal), combined.
glm::dvec3 combineNormals(const glm::dvec3& base, const glm::dvec3& detail, NormalBlend mode);

// Blends a decal into `surface`. `strength` is fades x opacity x mask (coverage comes from the
// textures); `surface_normal` the G-buffer's world normal; `has(t)` whether the frame has the
// target's plane. Returns true when some target changed.
bool applyDecal(const Decal& decal, const DecalValues& values, double strength, const glm::dvec3& surface_normal,
                const std::function<bool(DecalTarget)>& has, Surface& surface);

struct ShadeResult {
    std::map<Attribute, Plane> planes;  // every material plane of the frame, decals applied
    Plane albedo;                       // the same as planes[Albedo]
    // 1 where float rounding may legitimately flip the result: the point lies within `margin`
    // of a decal's box face, or a nearest lookup lies within `margin` of a texel edge.
    std::vector<std::uint8_t> ambiguous;
};
// Brute force: every pixel tests every decal in scene order.
ShadeResult shade(const GBuffer& frame, const Camera& camera, const DecalScene& scene,
                  double margin = 2e-5);

// Mixed pixels of a filtered frame (docs/profiles.md "Mixed pixels"): the normal pass shorter than
// 0.995, a background 4-neighbour or one more than 2 % away in view depth. Per pixel: 0 where not
// mixed, else the surface (non-background) pixels of its 3 x 3 neighbourhood, bit 3 (dy + 1) + dx + 1.
struct MixedPixels {
    int width = 0;
    std::vector<std::uint16_t> surfaces;  // empty: no pixel is treated as mixed
};
MixedPixels mixedPixels(const GBuffer& frame, const Camera& camera);

// The beauty update (docs/profiles.md "Beauty") where the albedo or emission of `after` differs from
// `before`: the beauty and, for multiplied light, the light terms of `planes` change. No relight.
// At `mixed` pixels divided light takes, per channel, the least of each term around the pixel.
void updateBeauty(const std::map<Attribute, Plane>& before, const std::map<Attribute, Plane>& after,
                  BeautyPlanes& planes, const MixedPixels& mixed = {});

}  // namespace decalcomp::reference
