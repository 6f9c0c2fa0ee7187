#include "decalcomp/mesh_file.hpp"

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <filesystem>
#include <map>
#include <utility>

#include "decalcomp/error.hpp"

namespace decalcomp {

RestMesh loadRestMesh(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw inputError(fmt::format("{}: mesh file not found (texture-space decals need the object's rest-pose "
                                     "mesh with UVs, as OBJ)",
                                     path));
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = "";  // materials play no part; a missing .mtl must not fail
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) {
        std::string why = reader.Error();
        while (!why.empty() && (why.back() == '\n' || why.back() == '\r')) why.pop_back();
        throw inputError(fmt::format("{}: not a readable OBJ mesh ({})", path, why.empty() ? "parse error" : why));
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    RestMesh mesh;
    mesh.source = path;
    std::map<std::pair<int, int>, int> corner_vertex;  // (v, vt) -> RestVertex
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        std::size_t first = 0;
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            const std::size_t n = shape.mesh.num_face_vertices[f];
            if (n != 3) throw inputError(fmt::format("{}: face {} of '{}' has {} corners after triangulation", path,
                                                     f + 1, shape.name, n));
            int corners[3];
            for (std::size_t k = 0; k < 3; ++k) {
                const tinyobj::index_t& index = shape.mesh.indices[first + k];
                if (index.texcoord_index < 0)
                    throw inputError(fmt::format("{}: face {} of '{}' has a corner without UVs (f v/vt): texture-space "
                                                 "decals need a UV map; unwrap the mesh and export with UVs",
                                                 path, f + 1, shape.name));
                const auto key = std::make_pair(index.vertex_index, index.texcoord_index);
                auto [it, inserted] = corner_vertex.emplace(key, int(mesh.vertices.size()));
                if (inserted) {
                    RestVertex v;
                    const auto p = std::size_t(index.vertex_index) * 3, t = std::size_t(index.texcoord_index) * 2;
                    v.position = glm::vec3(attrib.vertices[p], attrib.vertices[p + 1], attrib.vertices[p + 2]);
                    v.uv = glm::vec2(attrib.texcoords[t], attrib.texcoords[t + 1]);
                    mesh.vertices.push_back(v);
                }
                corners[k] = it->second;
            }
            mesh.triangles.emplace_back(corners[0], corners[1], corners[2]);
            first += n;
        }
    }
    if (mesh.triangles.empty()) throw inputError(fmt::format("{}: the mesh has no faces", path));
    finishRestMesh(mesh);
    return mesh;
}

}  // namespace decalcomp
