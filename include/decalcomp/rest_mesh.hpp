#pragma once
// A mesh in its rest pose with UVs, for texture-space decals (docs/texture-space.md): decals placed
// on the undeformed mesh reach a deformed frame through its UV pass. UV -> the rest triangle that
// holds it -> barycentric coordinates -> the rest-pose point the decal is evaluated at.
#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace decalcomp {

// One corner of the mesh: a distinct (position, UV) pair, so a UV seam splits a vertex in two.
struct RestVertex {
    glm::vec3 position{0.0f};  // rest pose, object space
    glm::vec2 uv{0.0f};        // v up (OpenGL, Blender), as OBJ files store it
    glm::vec3 normal{0.0f};    // area-weighted mean of its faces' normals
    glm::vec4 tangent{0.0f};   // xyz: dP/du made orthogonal to the normal; w: +-1, the sign of dP/dv
};

// A uniform grid over the mesh's UV bounding box: cell c lists (in cell_start[c] ..
// cell_start[c + 1] of `triangles`) every triangle whose UV bounding box meets it. About two
// triangles per cell, so a UV lookup tests a handful of triangles.
struct UvGrid {
    glm::vec2 origin{0.0f};         // UV of cell (0, 0)'s lower corner
    glm::vec2 cells_per_uv{1.0f};   // cells per UV unit along u and v
    int cells_x = 1, cells_y = 1;
    std::vector<int> cell_start;    // cells_x * cells_y + 1 offsets
    std::vector<int> triangles;     // triangle indices, cell by cell
};
struct RestMesh {
    std::string source;  // file it came from, for messages
    std::vector<RestVertex> vertices;
    std::vector<glm::ivec3> triangles;  // vertex indices, counter-clockwise seen from outside
    UvGrid grid;                        // built once with the mesh (finishRestMesh)
    int overlapping_uv_triangles = 0;   // countOverlappingUvTriangles, for the scene's warning
};

// Fills every vertex's normal and tangent frame from the triangles, in the way MikkTSpace does for
// smooth meshes: per face the tangent dP/du and bitangent dP/dv from the UVs, summed per vertex
// (weighted by the face's corner angle), then made orthogonal to the vertex normal; w records
// whether (tangent, bitangent, normal) is right-handed. Faces with degenerate UVs add no tangent;
// a vertex left without one gets any unit vector orthogonal to its normal.
void computeTangentFrames(RestMesh& mesh);

UvGrid buildUvGrid(const RestMesh& mesh);
// Tangent frames, the UV grid and the overlap count of a mesh whose vertices and triangles are set.
void finishRestMesh(RestMesh& mesh);

// Triangles whose UV interiors overlap another triangle's (mirrored or stacked islands): a UV there
// names two rest points, so texture-space decals need these to be none.
int countOverlappingUvTriangles(const RestMesh& mesh, const UvGrid& grid);

// Where a UV lands on the mesh: the triangle, barycentric weights of its corners and the rest
// point. nullopt when no triangle holds the UV (within kUvInsideTolerance of barycentric weight).
struct RestHit {
    int triangle = -1;
    glm::vec3 weights{0.0f};
    glm::vec3 position{0.0f};
};
constexpr float kUvInsideTolerance = 1e-5f;
std::optional<RestHit> findRestPoint(const RestMesh& mesh, glm::vec2 uv);  // through mesh.grid

}  // namespace decalcomp
