#pragma once
// The scalar reference of the texture-space bake (docs/texture-space.md "Bake mode"): double
// precision, brute force over the mesh's and its apron's triangles, written from the rule rather
// than from kernels/bake.cl. Tests compare the device's bake layers (bake.hpp) with it.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/decal.hpp"

namespace decalcomp::reference {

// What one bake texel stores for a decal evaluated at one rest point: premultiplied albedo (alpha:
// coverage x fades, also when the decal leaves the albedo alone), ORM and emission at that coverage
// (0 where the decal writes none there).
struct BakedTexel {
    glm::dvec4 albedo{0.0}, orm{0.0}, emission{0.0};
    bool ambiguous = false;  // a box face, a texel edge or a fade step within rounding of the point
};

// The decal of `scene` evaluated at rest points as the bake does: the mesh's rest normal for
// fades, texture footprints from the rest points one texel right and one texel down.
class BakeEvaluator {
public:
    BakeEvaluator(const DecalScene& scene, const Decal& decal, double margin = 2e-5);
    ~BakeEvaluator();
    BakedTexel at(const glm::dvec3& rest, const glm::dvec3& normal, const glm::dvec3& rest_dx,
                  const glm::dvec3& rest_dy) const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

// Per texel how it got its rest point.
enum class BakeTexelClass : std::uint8_t { Empty, Covered, Dilated };

struct BakeReference {
    int width = 0, height = 0;  // row 0 at v = 1, as the device layers
    std::vector<glm::dvec4> albedo, orm, emission;
    std::vector<BakeTexelClass> classes;
    // 1 where float rounding may flip the texel: which triangle covers or is nearest (the texel's
    // square within rounding of a triangle's edge, two candidates within rounding of each other),
    // whether it is covered at all, or the decal's own decisions (BakedTexel::ambiguous).
    std::vector<std::uint8_t> ambiguous;
};

// The layers of decal `decal` (a texture-space decal of `scene` in bake mode) at its
// bake_resolution and bake_dilation.
BakeReference bakeLayers(const DecalScene& scene, const Decal& decal, double margin = 2e-5);

}  // namespace decalcomp::reference
