#pragma once
// The reference's rest pass of texture-space decals (docs/texture-space.md), in double precision
// and world space, written from the rule rather than from kernels/rest_pose.cl: each object pixel's
// rest point through its UV, and the rotation taking rest-space directions to world space.
#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"
#include "decalcomp/rest_mesh.hpp"

namespace decalcomp::reference {

struct RestPixels {
    std::vector<std::optional<glm::dvec3>> points;  // per pixel: the rest point, nullopt = not reached
    std::vector<glm::dmat3> rotation;               // per pixel: rest -> world (identity where unknown)
    std::vector<std::uint8_t> ambiguous;            // float rounding may flip whether a triangle holds the UV
};

// `mask`: the frame's weight plane selecting the object (-1: every pixel). `world_normals`: the
// normal pass decoded to world space per pixel (empty: from the neighbours' points).
RestPixels restPixels(const GBuffer& frame, const Camera& camera, const RestMesh& mesh, int mask,
                      const std::vector<std::optional<glm::dvec3>>& world_normals);

// The rest point's difference towards the neighbour on axis (dx, dy) that the rest pass reached and
// that lies nearer (one across a fold or a silhouette lies far); nullopt when neither was reached.
std::optional<glm::dvec3> restStep(const RestPixels& rest, int width, int height, int x, int y, int dx, int dy);

}  // namespace decalcomp::reference
