#pragma once
// Deforming meshes with UVs ray-cast into G-buffers with a UV pass, for texture-space decal tests
// and benchmarks (docs/texture-space.md): the exact rest point of every pixel is known.
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"
#include "decalcomp/rest_mesh.hpp"

namespace decalcomp::synth {

// An open tube around +Z, radius `radius`, from z = 0 to `height`, `around` x `along` quads, in its
// rest pose (finishRestMesh done). UVs: one island with its seam at angle 0 (+X), u = 0.05 + 0.9 k /
// around, v = 0.05 + 0.9 z / height (v up).
RestMesh tubeMesh(int around, int along, double radius = 0.5, double height = 2.0);

// The tube's vertices twisted about Z (twist_deg at the top, linear in z) and then bent in the XZ
// plane (bend_deg over the whole height, base fixed), analytically per vertex.
std::vector<glm::vec3> twistAndBend(const RestMesh& mesh, double twist_deg, double bend_deg, double height = 2.0);

// A posed object: its rest mesh, its vertices in this frame (object = world space) and its id.
struct PosedMesh {
    const RestMesh* rest = nullptr;
    std::vector<glm::vec3> positions;
    int object_id = 1;
    glm::vec3 albedo{0.6f};
};

struct MeshFrame {
    GBuffer gbuffer;  // depth (planar, 1e10 background), albedo, normal (world), position, object_id, uv
    std::vector<std::optional<glm::dvec3>> rest_points;  // per pixel: the hit's point on its rest mesh
    std::vector<int> object;                             // per pixel: index into the meshes, -1 = none
};
// Nearest hit per pixel centre over every triangle (perspective-correct barycentrics); normals
// interpolate the posed mesh's area-weighted vertex normals, UVs the rest mesh's.
MeshFrame renderMeshes(const std::vector<PosedMesh>& meshes, const Camera& camera, int width, int height);

}  // namespace decalcomp::synth
