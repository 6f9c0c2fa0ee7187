#include "reference/occlusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "decalcomp/reference.hpp"

namespace decalcomp::reference {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMaxSlope = 16.0;  // tan of the steepest slope the bias follows

// Cube face f's axes (OpenGL rule): direction = major + sc * s_axis + tc * t_axis, sc = 2s - 1, tc = 2t - 1.
struct FaceAxes {
    glm::dvec3 major, s_axis, t_axis;
};
const FaceAxes kFaces[6] = {
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}}, {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},
    {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}}};

}  // namespace

BlastMap::BlastMap(const Decal& decal, const GBuffer& frame, const Camera& camera,
                   const std::function<double(const glm::dvec3&)>& slack_at)
    : decal_(decal), world_to_local_(glm::inverse(decal.world_matrix)), size_(occlusionMapSize(decal)) {
    upper_.assign(size_.texels(), kInf);
    lower_.assign(size_.texels(), kInf);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const auto P = pixelWorldPoint(frame, camera, x, y);
            if (!P) continue;
            const glm::dvec3 l(world_to_local_ * glm::dvec4(*P, 1.0));
            const double slack = slack_at(*P), dist = glm::length(l);
            bool sure = false, outside = false;
            for (const Texel& t : candidates(l, slack, sure, outside)) {
                const std::size_t k = index(t);
                lower_[k] = std::min(lower_[k], dist - slack);
                if (sure) upper_[k] = std::min(upper_[k], dist + slack);
            }
        }
}

std::optional<BlastMap::Texel> BlastMap::texelOf(const glm::dvec3& l) const {
    double s, t;
    Texel texel;
    if (decal_.kind == DecalKind::Cube) {
        const double r = glm::length(l);
        if (!(r > 0.0)) return std::nullopt;
        const CubeLookup c = cubeLookup(l / r);
        texel.face = c.face;
        s = c.s;
        t = c.t;
    } else {
        const double d = -l.z;
        if (!(d > 0.0)) return std::nullopt;
        const double half_h = d * std::tan(glm::radians(decal_.fov_y_deg) / 2.0);
        s = 0.5 + l.x / (2.0 * half_h * decal_.aspect);
        t = 0.5 - l.y / (2.0 * half_h);
        if (s < 0.0 || s > 1.0 || t < 0.0 || t > 1.0) return std::nullopt;
    }
    texel.i = std::min(int(std::floor(s * size_.width)), size_.width - 1);
    texel.j = std::min(int(std::floor(t * size_.height)), size_.height - 1);
    return texel;
}

std::vector<BlastMap::Texel> BlastMap::candidates(const glm::dvec3& l, double slack, bool& sure,
                                                  bool& some_outside) const {
    std::vector<Texel> out;
    some_outside = false;
    for (int corner = 0; corner < 9; ++corner) {
        glm::dvec3 moved = l;
        if (corner < 8)
            for (int a = 0; a < 3; ++a) moved[a] += (corner >> a & 1) ? slack : -slack;
        const auto t = texelOf(moved);
        if (!t) {
            some_outside = true;
            continue;
        }
        if (std::find(out.begin(), out.end(), *t) == out.end()) out.push_back(*t);
    }
    sure = !some_outside && out.size() == 1;
    return out;
}

std::vector<BlastMap::Texel> BlastMap::neighbourhood(const Texel& c) const {
    std::vector<Texel> out;
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
            Texel n{c.face, c.i + di, c.j + dj};
            if (n.i >= 0 && n.j >= 0 && n.i < size_.width && n.j < size_.height) {
                out.push_back(n);
            } else if (decal_.kind == DecalKind::Cube) {
                // past the face's edge: the texel that the off-face texel centre's direction hits
                const FaceAxes& f = kFaces[c.face];
                const double sc = 2.0 * (n.i + 0.5) / size_.width - 1.0, tc = 2.0 * (n.j + 0.5) / size_.height - 1.0;
                if (const auto t = texelOf(f.major + sc * f.s_axis + tc * f.t_axis)) out.push_back(*t);
            }
        }
    return out;
}

std::size_t BlastMap::index(const Texel& t) const {
    return (std::size_t(t.face) * size_.height + std::size_t(t.j)) * size_.width + std::size_t(t.i);
}

BlastVisibility BlastMap::test(const glm::dvec3& P, const glm::dvec3& n, double slack) const {
    BlastVisibility v;
    const glm::dvec3 l(world_to_local_ * glm::dvec4(P, 1.0));
    bool sure = false, outside = false;
    const std::vector<Texel> cands = candidates(l, slack, sure, outside);
    if (cands.empty()) return v;  // outside the map: nothing can hide it
    // least distance the kernel can read: over any candidate's neighbourhood (lower bound), and
    // at most the worst candidate's sure points (upper bound)
    double lower = kInf, upper = -kInf;
    for (const Texel& c : cands) {
        double candidate_upper = kInf;
        for (const Texel& t : neighbourhood(c)) {
            lower = std::min(lower, lower_[index(t)]);
            candidate_upper = std::min(candidate_upper, upper_[index(t)]);
        }
        upper = std::max(upper, candidate_upper);
    }
    const double dist = glm::length(l);
    // slope between the surface and the direction to the origin, in local space (normals map by M^T)
    const glm::dvec3 n_local = glm::normalize(glm::transpose(glm::dmat3(decal_.world_matrix)) * n);
    const double c = std::abs(glm::dot(n_local, l)) / dist;
    const double slope = c > 0.0 ? std::sqrt(std::max(1.0 - c * c, 0.0)) / c : kMaxSlope;
    const double tangent = decal_.kind == DecalKind::Cube
                               ? 2.0 / size_.width
                               : 2.0 * std::tan(glm::radians(decal_.fov_y_deg) / 2.0) *
                                     std::max(decal_.aspect / size_.width, 1.0 / size_.height);
    const double bias = decal_.occlusion.bias * dist * tangent * std::clamp(slope, 1.0, kMaxSlope);
    const double bias_slack = 1e-3 * bias + slack;
    const bool surely_reaches = dist + slack <= lower + bias - bias_slack;
    const bool surely_blocked = dist - slack > upper + bias + bias_slack;
    v.reaches = !surely_blocked;
    v.ambiguous = outside || !(surely_reaches || surely_blocked);
    return v;
}

}  // namespace decalcomp::reference
