#pragma once
// One decal evaluated at one point, as reference::shade does it (reference.cpp): shared with the
// reference bake (bake.cpp), which evaluates decals at rest points of texels instead of pixels,
// and with the pixel filter's closed form (filter_integral.cpp).
#include <cstddef>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/decal.hpp"
#include "decalcomp/reference.hpp"

namespace decalcomp::reference {

// Where the rays of the pixel's right and lower neighbours meet the tangent plane (world space).
struct Footprint {
    bool valid = false;
    glm::dvec3 dx{0.0}, dy{0.0};
};

// A premultiplied texel's straight colour; nullopt where it has no coverage (materials.cpp).
std::optional<glm::dvec3> straight(const std::optional<glm::dvec4>& texel);

// A decal at one world point: the kind's falloff and fades, and where its textures are looked up
// (docs/conventions.md "Decals").
struct DecalHit {
    double fade = 0.0;  // 0 = outside or faded out
    bool ambiguous = false;
    glm::dvec3 local{0.0}, local_dx{0.0}, local_dy{0.0};  // the point and its footprint in decal space
    bool footprint = false;
    bool filtered = false;  // a pixel-filter tap: local_dx/dy span its stratum
    CubeLookup cube;
    double direction_slack = 0.0;    // cube: rounding of the direction
    glm::dvec3 facing{0.0};          // world direction a receiving surface faces
    glm::dvec3 right{0.0}, up{0.0};  // world directions of growing s and falling t
};

// A cube decal's facing, face (ambiguous within rounding of a face edge) and face image's right and
// up, at local point l (0 < |l| <= 0.5) of world point P.
void cubeFaceAt(const Decal& decal, const glm::dvec3& l, const glm::dvec3& P, double slack, DecalHit& out);

// A pixel-filter tap's stratum in decal space: the local vectors it spans.
struct Stratum {
    glm::dvec3 su{0.0}, sv{0.0};
};

// The decal at point P (the decal's world, or a mesh's rest space for texture-space decals):
// inside test, falloff and fades (with `normal` where given), texture coordinates and the
// footprint's. `slack`: how far rounding may move a local coordinate (sets `ambiguous`).
DecalHit hitDecal(const Decal& decal, const glm::dmat4& world_to_local, const glm::dvec3& P,
                  const std::optional<glm::dvec3>& normal, const Footprint& footprint, double slack,
                  const Stratum* stratum = nullptr);

// A texture of the decal's set at the hit, with the decal's filter (premultiplied RGBA); sets
// `ambiguous` when a nearest lookup lies within rounding of a texel edge.
glm::dvec4 hitTexel(const DecalHit& hit, const Decal& decal, const Texture2D& t, const std::vector<Texture2D>& chain,
                    double slack, bool& ambiguous);

// hitTexel, the footprint's texture coordinates scaled by `scale` around the hit's (the closed
// form's read over the filter's equivalent box, dc_integrated_texel: local_dx/dy one pixel away).
glm::dvec4 hitTexelScaled(const DecalHit& hit, const Decal& decal, const Texture2D& t,
                          const std::vector<Texture2D>& chain, double slack, bool& ambiguous, double scale);

// What the decal offers at a hit: each of its textures as `read(texture index)` gives it
// (premultiplied RGBA; none where the decal has no such texture) and the hit's world directions.
template <class Read>
DecalValues valuesAtHit(const Decal& decal, const DecalHit& hit, Read read) {
    auto texel = [&](int texture) {
        if (texture < 0) return std::optional<glm::dvec4>();
        return std::optional<glm::dvec4>(read(std::size_t(texture)));
    };
    DecalValues values;
    values.albedo = texel(decal.albedo_texture);
    values.normal = texel(decal.normal_texture);
    values.orm = texel(decal.orm_texture);
    values.emission = texel(decal.emission_texture);
    values.facing = hit.facing;
    values.right = hit.right;
    values.up = hit.up;
    return values;
}

// Texel (i, j) of slice `slice`, each clamped to the texture.
glm::dvec4 texelAt(const Texture2D& texture, long i, long j, long slice);

// 1 up to `full`, 0 from `none`, linear between.
double rampDown(double x, double full, double none);

}  // namespace decalcomp::reference
