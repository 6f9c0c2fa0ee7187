#include "decalcomp/rest_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace decalcomp {

namespace {

float cornerAngle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 u = b - a, v = c - a;
    return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

glm::vec3 anyOrthogonal(const glm::vec3& n) {
    const glm::vec3 axis = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    return glm::normalize(glm::cross(axis, n));
}

struct UvBox {
    glm::vec2 lo, hi;
};

UvBox triangleBox(const RestMesh& mesh, const glm::ivec3& t) {
    const glm::vec2 a = mesh.vertices[std::size_t(t.x)].uv, b = mesh.vertices[std::size_t(t.y)].uv,
                    c = mesh.vertices[std::size_t(t.z)].uv;
    return {glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))};
}

// The cells of `grid` a UV box meets, as an inclusive range.
void cellRange(const UvGrid& grid, const UvBox& box, int& x0, int& y0, int& x1, int& y1) {
    const glm::vec2 lo = (box.lo - grid.origin) * grid.cells_per_uv, hi = (box.hi - grid.origin) * grid.cells_per_uv;
    x0 = std::clamp(int(std::floor(lo.x)), 0, grid.cells_x - 1);
    y0 = std::clamp(int(std::floor(lo.y)), 0, grid.cells_y - 1);
    x1 = std::clamp(int(std::floor(hi.x)), 0, grid.cells_x - 1);
    y1 = std::clamp(int(std::floor(hi.y)), 0, grid.cells_y - 1);
}

// Barycentric weights of p in the UV triangle (a, b, c); nullopt when it has no area.
std::optional<glm::vec3> barycentric(glm::vec2 a, glm::vec2 b, glm::vec2 c, glm::vec2 p) {
    const glm::vec2 e0 = b - a, e1 = c - a, d = p - a;
    const float det = e0.x * e1.y - e0.y * e1.x;
    if (!(std::abs(det) > 0.0f)) return std::nullopt;
    const float wb = (d.x * e1.y - d.y * e1.x) / det, wc = (e0.x * d.y - e0.y * d.x) / det;
    return glm::vec3(1.0f - wb - wc, wb, wc);
}

// Whether two UV triangles' interiors overlap: no edge normal of either separates them by more
// than `eps` (triangles that share an edge or a corner touch without overlapping).
bool interiorsOverlap(const glm::vec2 p[3], const glm::vec2 q[3], float eps) {
    for (const glm::vec2* tri : {p, q})
        for (int e = 0; e < 3; ++e) {
            const glm::vec2 edge = tri[(e + 1) % 3] - tri[e];
            const glm::vec2 axis(-edge.y, edge.x);
            const float len = glm::length(axis);
            if (!(len > 0.0f)) continue;
            float pmin = 1e30f, pmax = -1e30f, qmin = 1e30f, qmax = -1e30f;
            for (int k = 0; k < 3; ++k) {
                const float a = glm::dot(p[k], axis) / len, b = glm::dot(q[k], axis) / len;
                pmin = std::min(pmin, a);
                pmax = std::max(pmax, a);
                qmin = std::min(qmin, b);
                qmax = std::max(qmax, b);
            }
            if (pmax <= qmin + eps || qmax <= pmin + eps) return false;
        }
    return true;
}

}  // namespace

void computeTangentFrames(RestMesh& mesh) {
    std::vector<glm::vec3> normals(mesh.vertices.size(), glm::vec3(0.0f)), tangents(normals), bitangents(normals);
    for (const glm::ivec3& t : mesh.triangles) {
        const int idx[3] = {t.x, t.y, t.z};
        const RestVertex &a = mesh.vertices[std::size_t(t.x)], &b = mesh.vertices[std::size_t(t.y)],
                         &c = mesh.vertices[std::size_t(t.z)];
        const glm::vec3 e0 = b.position - a.position, e1 = c.position - a.position;
        const glm::vec3 face = glm::cross(e0, e1);  // length: twice the area
        const glm::vec2 d0 = b.uv - a.uv, d1 = c.uv - a.uv;
        const float det = d0.x * d1.y - d0.y * d1.x;
        glm::vec3 dpdu(0.0f), dpdv(0.0f);
        if (std::abs(det) > 1e-20f) {
            dpdu = (e0 * d1.y - e1 * d0.y) / det;
            dpdv = (e1 * d0.x - e0 * d1.x) / det;
        }
        const glm::vec3 corners[3] = {a.position, b.position, c.position};
        for (int k = 0; k < 3; ++k) {
            const float angle = cornerAngle(corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]);
            const auto v = std::size_t(idx[k]);
            normals[v] += face;  // area weighted
            if (glm::length(dpdu) > 0.0f) tangents[v] += glm::normalize(dpdu) * angle;
            if (glm::length(dpdv) > 0.0f) bitangents[v] += glm::normalize(dpdv) * angle;
        }
    }
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        RestVertex& vertex = mesh.vertices[v];
        vertex.normal = glm::length(normals[v]) > 0.0f ? glm::normalize(normals[v]) : glm::vec3(0, 0, 1);
        const glm::vec3 t = tangents[v] - vertex.normal * glm::dot(vertex.normal, tangents[v]);
        const glm::vec3 tangent = glm::length(t) > 1e-12f ? glm::normalize(t) : anyOrthogonal(vertex.normal);
        const float handedness = glm::dot(glm::cross(vertex.normal, tangent), bitangents[v]) < 0.0f ? -1.0f : 1.0f;
        vertex.tangent = glm::vec4(tangent, handedness);
    }
}

UvGrid buildUvGrid(const RestMesh& mesh) {
    UvGrid grid;
    if (mesh.triangles.empty()) {
        grid.cell_start = {0, 0};
        return grid;
    }
    UvBox all{glm::vec2(1e30f), glm::vec2(-1e30f)};
    for (const RestVertex& v : mesh.vertices) {
        all.lo = glm::min(all.lo, v.uv);
        all.hi = glm::max(all.hi, v.uv);
    }
    const glm::vec2 size = glm::max(all.hi - all.lo, glm::vec2(1e-6f));
    // Square cells, twice as many as triangles: a triangle's box then covers a few cells and a cell
    // lists few triangles. Measured on the bench's 102,400-triangle tube (PoCL, 1080p): the device
    // lookup took 16.7 ms with half as many cells as triangles, 14.5 ms with twice, 14.2 with four
    // times (docs/benchmarks.md "Texture-space decals").
    const double cell = std::sqrt(double(size.x) * size.y / std::max<double>(1.0, 2.0 * double(mesh.triangles.size())));
    grid.cells_x = std::clamp(int(std::ceil(size.x / cell)), 1, 4096);
    grid.cells_y = std::clamp(int(std::ceil(size.y / cell)), 1, 4096);
    grid.origin = all.lo;
    grid.cells_per_uv = glm::vec2(float(grid.cells_x) / size.x, float(grid.cells_y) / size.y);
    const std::size_t cells = std::size_t(grid.cells_x) * std::size_t(grid.cells_y);
    std::vector<int> counts(cells + 1, 0);
    auto forCells = [&](const glm::ivec3& t, auto&& visit) {
        int x0, y0, x1, y1;
        cellRange(grid, triangleBox(mesh, t), x0, y0, x1, y1);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) visit(std::size_t(y) * std::size_t(grid.cells_x) + std::size_t(x));
    };
    for (const glm::ivec3& t : mesh.triangles) forCells(t, [&](std::size_t c) { ++counts[c + 1]; });
    for (std::size_t c = 0; c < cells; ++c) counts[c + 1] += counts[c];
    grid.cell_start = counts;
    grid.triangles.assign(std::size_t(counts[cells]), 0);
    std::vector<int> fill(counts.begin(), counts.end() - 1);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        forCells(mesh.triangles[i], [&](std::size_t c) { grid.triangles[std::size_t(fill[c]++)] = int(i); });
    return grid;
}

int countOverlappingUvTriangles(const RestMesh& mesh, const UvGrid& grid) {
    std::vector<char> overlapping(mesh.triangles.size(), 0);
    auto corners = [&](int t, glm::vec2 out[3]) {
        const glm::ivec3& tri = mesh.triangles[std::size_t(t)];
        out[0] = mesh.vertices[std::size_t(tri.x)].uv;
        out[1] = mesh.vertices[std::size_t(tri.y)].uv;
        out[2] = mesh.vertices[std::size_t(tri.z)].uv;
    };
    constexpr float eps = 1e-7f;  // UV units: float rounding of shared edges is not an overlap
    for (std::size_t c = 0; c + 1 < grid.cell_start.size(); ++c)
        for (int i = grid.cell_start[c]; i < grid.cell_start[c + 1]; ++i)
            for (int j = i + 1; j < grid.cell_start[c + 1]; ++j) {
                const int a = grid.triangles[std::size_t(i)], b = grid.triangles[std::size_t(j)];
                if (overlapping[std::size_t(a)] && overlapping[std::size_t(b)]) continue;
                glm::vec2 p[3], q[3];
                corners(a, p);
                corners(b, q);
                if (interiorsOverlap(p, q, eps)) overlapping[std::size_t(a)] = overlapping[std::size_t(b)] = 1;
            }
    return int(std::count(overlapping.begin(), overlapping.end(), 1));
}

void finishRestMesh(RestMesh& mesh) {
    computeTangentFrames(mesh);
    mesh.grid = buildUvGrid(mesh);
    mesh.overlapping_uv_triangles = countOverlappingUvTriangles(mesh, mesh.grid);
}

std::optional<RestHit> findRestPoint(const RestMesh& mesh, glm::vec2 uv) {
    const UvGrid& grid = mesh.grid;
    if (grid.cell_start.size() < 2) return std::nullopt;
    const glm::vec2 g = (uv - grid.origin) * grid.cells_per_uv;
    // A UV on the grid's far edge belongs to the last cell; beyond the grid nothing holds it.
    const int x = int(std::floor(g.x)), y = int(std::floor(g.y));
    if (!(g.x >= -1e-3f && g.y >= -1e-3f && g.x <= float(grid.cells_x) + 1e-3f && g.y <= float(grid.cells_y) + 1e-3f))
        return std::nullopt;
    const std::size_t c = std::size_t(std::clamp(y, 0, grid.cells_y - 1)) * std::size_t(grid.cells_x) +
                          std::size_t(std::clamp(x, 0, grid.cells_x - 1));
    RestHit best;
    float best_inside = -1e30f;
    for (int i = grid.cell_start[c]; i < grid.cell_start[c + 1]; ++i) {
        const int t = grid.triangles[std::size_t(i)];
        const glm::ivec3& tri = mesh.triangles[std::size_t(t)];
        const auto w = barycentric(mesh.vertices[std::size_t(tri.x)].uv, mesh.vertices[std::size_t(tri.y)].uv,
                                   mesh.vertices[std::size_t(tri.z)].uv, uv);
        if (!w) continue;
        const float inside = std::min(w->x, std::min(w->y, w->z));
        if (inside > best_inside) {
            best_inside = inside;
            best.triangle = t;
            best.weights = *w;
        }
    }
    if (best.triangle < 0 || best_inside < -kUvInsideTolerance) return std::nullopt;
    const glm::ivec3& tri = mesh.triangles[std::size_t(best.triangle)];
    best.position = mesh.vertices[std::size_t(tri.x)].position * best.weights.x +
                    mesh.vertices[std::size_t(tri.y)].position * best.weights.y +
                    mesh.vertices[std::size_t(tri.z)].position * best.weights.z;
    return best;
}

}  // namespace decalcomp
