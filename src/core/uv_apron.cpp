// The apron around a mesh's UV islands (bake.hpp, docs/texture-space.md "Bake mode"): what the bake
// writes just outside an island so that filtered lookups near its border read the surface that
// continues there, not an empty texel.
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <utility>

#include "decalcomp/bake.hpp"

namespace decalcomp {

namespace {

// Rest positions as exact bit patterns: the corners a UV seam splits share one OBJ `v`.
using PositionKey = std::array<std::uint32_t, 3>;
PositionKey positionKey(const glm::vec3& p) {
    PositionKey key;
    std::memcpy(key.data(), &p, sizeof key);
    return key;
}

float cross2(glm::vec2 a, glm::vec2 b) { return a.x * b.y - a.y * b.x; }

// `p` in the frame of the UV edge (a, b): along it (0 at a, 1 at b) and across it, in units of its length.
glm::vec2 edgeCoordinates(glm::vec2 a, glm::vec2 b, glm::vec2 p) {
    const glm::vec2 e = b - a;
    const float len2 = glm::dot(e, e);
    return {glm::dot(p - a, e) / len2, cross2(e, p - a) / len2};
}
glm::vec2 fromEdgeCoordinates(glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    const glm::vec2 e = b - a;
    return a + e * c.x + glm::vec2(-e.y, e.x) * c.y;
}

}  // namespace

RestMesh uvApron(const RestMesh& mesh) {
    RestMesh apron;
    apron.source = mesh.source + " (UV apron)";
    // UV edges by their two corners, and 3D edges by their two positions: an island border edge has
    // no other triangle on the same corners; its twin across a seam shares the positions.
    std::map<std::pair<int, int>, int> uv_edges;
    std::map<std::pair<PositionKey, PositionKey>, std::vector<std::pair<int, int>>> edges3d;  // (triangle, edge)
    auto sorted = [](auto a, auto b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); };
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
            ++uv_edges[sorted(a, b)];
            edges3d[sorted(positionKey(mesh.vertices[std::size_t(a)].position),
                           positionKey(mesh.vertices[std::size_t(b)].position))]
                .emplace_back(int(t), k);
        }
    auto addVertex = [&](glm::vec3 position, glm::vec2 uv, glm::vec3 normal) {
        RestVertex v;
        v.position = position;
        v.uv = uv;
        v.normal = normal;
        apron.vertices.push_back(v);
        return int(apron.vertices.size()) - 1;
    };
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const RestVertex& a = mesh.vertices[std::size_t(mesh.triangles[t][k])];
            const RestVertex& b = mesh.vertices[std::size_t(mesh.triangles[t][(k + 1) % 3])];
            const RestVertex& o = mesh.vertices[std::size_t(mesh.triangles[t][(k + 2) % 3])];
            if (uv_edges[sorted(mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3])] > 1) continue;  // inside an island
            if (!(glm::length(b.uv - a.uv) > 0.0f)) continue;
            const float o_side = edgeCoordinates(a.uv, b.uv, o.uv).y;
            if (!(std::abs(o_side) > 0.0f)) continue;
            glm::vec2 apex_uv;
            glm::vec3 apex_position, apex_normal;
            const RestVertex* twin_apex = nullptr;
            const RestVertex *twin_a = nullptr, *twin_b = nullptr;
            for (const auto& [u, e] : edges3d[sorted(positionKey(a.position), positionKey(b.position))]) {
                if (u == int(t)) continue;
                const RestVertex& p = mesh.vertices[std::size_t(mesh.triangles[std::size_t(u)][e])];
                const RestVertex& q = mesh.vertices[std::size_t(mesh.triangles[std::size_t(u)][(e + 1) % 3])];
                twin_a = p.position == a.position ? &p : &q;
                twin_b = p.position == a.position ? &q : &p;
                twin_apex = &mesh.vertices[std::size_t(mesh.triangles[std::size_t(u)][(e + 2) % 3])];
                break;
            }
            if (twin_apex && glm::length(twin_b->uv - twin_a->uv) > 0.0f) {
                // the face across the seam, its shape in its own chart carried onto this edge, on
                // the side away from this face
                glm::vec2 c = edgeCoordinates(twin_a->uv, twin_b->uv, twin_apex->uv);
                c.y = std::abs(c.y) * (o_side > 0.0f ? -1.0f : 1.0f);
                apex_uv = fromEdgeCoordinates(a.uv, b.uv, c);
                apex_position = twin_apex->position;
                apex_normal = twin_apex->normal;
            } else {
                // the mesh ends here: this face mirrored, its plane extended
                const glm::vec2 c = edgeCoordinates(a.uv, b.uv, o.uv);
                apex_uv = fromEdgeCoordinates(a.uv, b.uv, glm::vec2(c.x, -c.y));
                const glm::vec3 along = a.position + (b.position - a.position) * c.x;
                apex_position = 2.0f * along - o.position;
                apex_normal = o.normal;
            }
            const int va = addVertex(a.position, a.uv, a.normal), vb = addVertex(b.position, b.uv, b.normal);
            const int vc = addVertex(apex_position, apex_uv, apex_normal);
            apron.triangles.emplace_back(va, vb, vc);
        }
    apron.grid = buildUvGrid(apron);
    return apron;
}

std::uint64_t restMeshFingerprint(const RestMesh& mesh) {
    std::uint64_t hash = 14695981039346656037ull;  // FNV-1a 64
    auto add = [&](const void* data, std::size_t size) {
        const auto* bytes = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 1099511628211ull;
    };
    for (const RestVertex& v : mesh.vertices) {
        add(&v.position, sizeof v.position);
        add(&v.uv, sizeof v.uv);
    }
    for (const glm::ivec3& t : mesh.triangles) add(&t, sizeof t);
    return hash;
}

}  // namespace decalcomp
