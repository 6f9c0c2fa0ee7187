#pragma once
// Blast occlusion in double (docs/conventions.md "Blast occlusion"), brute force over the frame's
// points, with the bounds float rounding can move the kernel's map and test within.
#include <functional>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp::reference {

struct BlastVisibility {
    bool reaches = true;
    bool ambiguous = false;  // float rounding of the map or the test could flip `reaches`
};

class BlastMap {
public:
    // `slack_at(P)`: how far rounding can move the decal-local point of world point P.
    BlastMap(const Decal& decal, const GBuffer& frame, const Camera& camera,
             const std::function<double(const glm::dvec3&)>& slack_at);
    // World point P with world normal n (unit), at rounding slack `slack`.
    BlastVisibility test(const glm::dvec3& P, const glm::dvec3& n, double slack) const;

private:
    struct Texel {
        int face = 0, i = 0, j = 0;
        bool operator==(const Texel&) const = default;
    };
    std::optional<Texel> texelOf(const glm::dvec3& local) const;
    // The texels a local point may fall in when each coordinate moves by up to `slack`; `sure`
    // says all moves land in the same texel.
    std::vector<Texel> candidates(const glm::dvec3& local, double slack, bool& sure, bool& some_outside) const;
    std::vector<Texel> neighbourhood(const Texel& t) const;
    std::size_t index(const Texel& t) const;

    Decal decal_;
    glm::dmat4 world_to_local_;
    OcclusionMapSize size_;
    std::vector<double> upper_, lower_;  // bounds on the kernel's least distance per texel
};

}  // namespace decalcomp::reference
