#pragma once
// Rest-pose meshes from files (tinyobjloader: OBJ, docs/texture-space.md).
#include <string>

#include "decalcomp/rest_mesh.hpp"

namespace decalcomp {

// Reads an OBJ mesh with UVs: polygons are triangulated, every (v, vt) pair becomes one
// RestVertex, then finishRestMesh (tangent frames from the UVs, the file's own vn unused so tangents
// and normals agree; the UV grid; the overlap count). Throws Error(Input) naming the file: unreadable, no faces,
// no UVs, a face corner without vt.
RestMesh loadRestMesh(const std::string& path);

}  // namespace decalcomp
