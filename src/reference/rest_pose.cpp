#include "reference/rest_pose.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "decalcomp/reference.hpp"

namespace decalcomp::reference {

namespace {

// Triangles bucketed by their UV boxes on a fixed 64 x 64 grid over the unit square's multiples
// the mesh covers; a plain, independent index (the library's UvGrid sizes cells by density).
class UvBuckets {
public:
    explicit UvBuckets(const RestMesh& mesh) : mesh_(mesh) {
        lo_ = glm::dvec2(std::numeric_limits<double>::max());
        hi_ = -lo_;
        for (const RestVertex& v : mesh.vertices) {
            lo_ = glm::min(lo_, glm::dvec2(v.uv));
            hi_ = glm::max(hi_, glm::dvec2(v.uv));
        }
        buckets_.resize(kSide * kSide);
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            glm::dvec2 a(1e300), b(-1e300);
            for (int k = 0; k < 3; ++k) {
                const glm::dvec2 uv(mesh.vertices[std::size_t(mesh.triangles[t][k])].uv);
                a = glm::min(a, uv);
                b = glm::max(b, uv);
            }
            const glm::ivec2 c0 = bucket(a), c1 = bucket(b);
            for (int y = c0.y; y <= c1.y; ++y)
                for (int x = c0.x; x <= c1.x; ++x) buckets_[std::size_t(y * kSide + x)].push_back(int(t));
        }
    }

    // The triangle that holds uv best (largest smallest barycentric weight) and its weights.
    struct Hit {
        int triangle = -1;
        glm::dvec3 w{0.0};
        double inside = -1e300;
    };
    Hit find(const glm::dvec2& uv) const {
        Hit best;
        const glm::dvec2 g = (uv - lo_) / glm::max(hi_ - lo_, glm::dvec2(1e-300)) * double(kSide);
        if (!(g.x >= -0.5 && g.y >= -0.5 && g.x <= kSide + 0.5 && g.y <= kSide + 0.5)) return best;
        for (int t : buckets_[std::size_t(bucket(uv).y * kSide + bucket(uv).x)]) {
            const glm::ivec3& tri = mesh_.triangles[std::size_t(t)];
            const glm::dvec2 a(mesh_.vertices[std::size_t(tri.x)].uv), b(mesh_.vertices[std::size_t(tri.y)].uv),
                c(mesh_.vertices[std::size_t(tri.z)].uv);
            const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
            if (area == 0.0) continue;
            // weights as ratios of sub-triangle areas
            auto cross2 = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {
                return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
            };
            const glm::dvec3 w(cross2(uv, b, c) / area, cross2(a, uv, c) / area, cross2(a, b, uv) / area);
            const double inside = std::min(w.x, std::min(w.y, w.z));
            if (inside > best.inside) best = {t, w, inside};
        }
        return best;
    }

private:
    static constexpr int kSide = 64;
    const RestMesh& mesh_;
    glm::dvec2 lo_, hi_;
    std::vector<std::vector<int>> buckets_;
    glm::ivec2 bucket(const glm::dvec2& uv) const {
        const glm::dvec2 g = (uv - lo_) / glm::max(hi_ - lo_, glm::dvec2(1e-300)) * double(kSide);
        return glm::clamp(glm::ivec2(glm::floor(g)), glm::ivec2(0), glm::ivec2(kSide - 1));
    }
};

glm::dvec3 interpolate(const RestMesh& mesh, int t, const glm::dvec3& w, glm::vec3 RestVertex::*field) {
    const glm::ivec3& tri = mesh.triangles[std::size_t(t)];
    return w.x * glm::dvec3(mesh.vertices[std::size_t(tri.x)].*field) +
           w.y * glm::dvec3(mesh.vertices[std::size_t(tri.y)].*field) +
           w.z * glm::dvec3(mesh.vertices[std::size_t(tri.z)].*field);
}

glm::dvec3 tangentAt(const RestMesh& mesh, int t, const glm::dvec3& w) {
    const glm::ivec3& tri = mesh.triangles[std::size_t(t)];
    glm::dvec3 sum(0.0);
    for (int k = 0; k < 3; ++k) sum += w[k] * glm::dvec3(glm::vec3(mesh.vertices[std::size_t(tri[k])].tangent));
    return sum;
}

// Rotation taking unit a to unit b along the shortest arc (Rodrigues).
glm::dmat3 shortestArc(const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 v = glm::cross(a, b);
    const double c = glm::dot(a, b);
    if (c < -0.999999) {
        const glm::dvec3 axis = glm::normalize(std::abs(a.x) < 0.9 ? glm::cross(a, glm::dvec3(1, 0, 0))
                                                                    : glm::cross(a, glm::dvec3(0, 1, 0)));
        return 2.0 * glm::outerProduct(axis, axis) - glm::dmat3(1.0);
    }
    const glm::dmat3 k(0, v.z, -v.y, -v.z, 0, v.x, v.y, -v.x, 0);  // column-major cross-product matrix
    return glm::dmat3(1.0) + k + k * k * (1.0 / (1.0 + c));
}

}  // namespace

RestPixels restPixels(const GBuffer& frame, const Camera& camera, const RestMesh& mesh, int mask,
                      const std::vector<std::optional<glm::dvec3>>& world_normals) {
    const std::size_t pixels = frame.pixelCount();
    RestPixels out;
    out.points.assign(pixels, std::nullopt);
    out.rotation.assign(pixels, glm::dmat3(1.0));
    out.ambiguous.assign(pixels, 0);
    const auto uv_plane = frame.planes.find(Attribute::UV);
    if (uv_plane == frame.planes.end()) return out;
    const UvBuckets buckets(mesh);
    std::vector<int> triangle(pixels, -1);
    std::vector<glm::dvec3> weights(pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
        if (mask >= 0 && !(frame.mask_weights[std::size_t(mask)].at(i, 0) > 0.0f)) continue;
        glm::dvec2 uv(uv_plane->second.at(i, 0), uv_plane->second.at(i, 1));
        if (frame.uv_v_down) uv.y = 1.0 - uv.y;
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) continue;
        const UvBuckets::Hit hit = buckets.find(uv);
        if (hit.triangle < 0) continue;
        if (std::abs(hit.inside + double(kUvInsideTolerance)) < 2e-6) out.ambiguous[i] = 1;
        if (hit.inside < -double(kUvInsideTolerance)) continue;
        triangle[i] = hit.triangle;
        weights[i] = hit.w;
        out.points[i] = interpolate(mesh, hit.triangle, hit.w, &RestVertex::position);
    }
    // Rotations: the mesh's normal to the pixel's, its tangent to its image under the deformation
    // the neighbours' rest and world points show (the nearer neighbour on each axis).
    std::vector<std::optional<glm::dvec3>> world(pixels);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x)
            if (out.points[std::size_t(y) * frame.width + x]) world[std::size_t(y) * frame.width + x] = pixelWorldPoint(frame, camera, x, y);
    const glm::dvec3 eye(glm::inverse(camera.world_to_camera)[3]);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const std::size_t i = std::size_t(y) * frame.width + x;
            if (!out.points[i] || !world[i]) continue;
            auto difference = [&](int dx, int dy, glm::dvec3& d_rest, glm::dvec3& d_world) {
                double best = std::numeric_limits<double>::max();
                for (int side : {1, -1}) {
                    const int nx = x + side * dx, ny = y + side * dy;
                    if (nx < 0 || ny < 0 || nx >= frame.width || ny >= frame.height) continue;
                    const std::size_t j = std::size_t(ny) * frame.width + nx;
                    if (!out.points[j] || !world[j]) continue;
                    const double dist = glm::length(*world[j] - *world[i]);
                    if (dist < best) {
                        best = dist;
                        d_rest = *out.points[j] - *out.points[i];
                        d_world = *world[j] - *world[i];
                    }
                }
                return best < std::numeric_limits<double>::max() && glm::length(d_rest) > 0.0;
            };
            glm::dvec3 a, A, b, B;
            const bool has_x = difference(1, 0, a, A), has_y = difference(0, 1, b, B);
            const glm::dvec3 rest_normal = glm::normalize(interpolate(mesh, triangle[i], weights[i], &RestVertex::normal));
            glm::dvec3 tangent = tangentAt(mesh, triangle[i], weights[i]);
            tangent = glm::normalize(tangent - rest_normal * glm::dot(rest_normal, tangent));
            glm::dvec3 n;
            if (!world_normals.empty() && world_normals[i]) {
                n = *world_normals[i];
            } else if (has_x && has_y) {
                n = glm::normalize(glm::cross(A, B));
                if (glm::dot(n, *world[i] - eye) > 0.0) n = -n;
            } else {
                continue;
            }
            out.rotation[i] = shortestArc(rest_normal, n);
            if (!has_x || !has_y) continue;
            const double aa = glm::dot(a, a), ab = glm::dot(a, b), bb = glm::dot(b, b), det = aa * bb - ab * ab;
            if (!(det > 1e-12 * aa * bb)) continue;
            const double ta = glm::dot(tangent, a), tb = glm::dot(tangent, b);
            glm::dvec3 t = (ta * bb - tb * ab) / det * A + (tb * aa - ta * ab) / det * B;
            t -= n * glm::dot(n, t);
            if (!(glm::length(t) > 1e-12)) continue;
            const glm::dvec3 f1 = glm::normalize(t), f2 = glm::cross(n, f1);
            const glm::dvec3 e2 = glm::cross(rest_normal, tangent);
            out.rotation[i] = glm::outerProduct(f1, tangent) + glm::outerProduct(f2, e2) + glm::outerProduct(n, rest_normal);
        }
    return out;
}

std::optional<glm::dvec3> restStep(const RestPixels& rest, int width, int height, int x, int y, int dx, int dy) {
    const glm::dvec3 P = *rest.points[std::size_t(y) * width + x];
    std::optional<glm::dvec3> best;
    for (int side = 1; side >= -1; side -= 2) {
        const int nx = x + side * dx, ny = y + side * dy;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const auto& q = rest.points[std::size_t(ny) * width + nx];
        if (!q) continue;
        const glm::dvec3 d = (*q - P) * double(side);
        if (!best || glm::length(d) < glm::length(*best)) best = d;
    }
    return best;
}

}  // namespace decalcomp::reference
