#include "decalcomp/normal_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "decalcomp/geometry.hpp"

namespace decalcomp {

namespace {

constexpr std::size_t kMaxSamples = 4000;
// A reading is adopted when its agreement is high and it is the one given (profile or flags) or
// beats the others clearly.
constexpr double kGoodAgreement = 0.9, kMargin = 0.2;

// Normal of the surface at pixel (x, y) from its four neighbours' points, facing the camera;
// nullopt where a neighbour is missing or the surface bends or breaks there (a silhouette).
std::optional<glm::dvec3> geometricNormal(const GBuffer& g, const Camera& camera, const glm::dvec3& eye, int x, int y) {
    if (x < 1 || y < 1 || x + 1 >= g.width || y + 1 >= g.height) return std::nullopt;
    const auto p = pixelWorldPoint(g, camera, x, y);
    const auto l = pixelWorldPoint(g, camera, x - 1, y), r = pixelWorldPoint(g, camera, x + 1, y);
    const auto u = pixelWorldPoint(g, camera, x, y - 1), d = pixelWorldPoint(g, camera, x, y + 1);
    if (!p || !l || !r || !u || !d) return std::nullopt;
    // smooth: each side's step about as long as the other's
    auto smooth = [](const glm::dvec3& a, const glm::dvec3& b) {
        const double la = glm::length(a), lb = glm::length(b);
        return la > 0 && lb > 0 && std::max(la, lb) < 1.5 * std::min(la, lb);
    };
    if (!smooth(*r - *p, *p - *l) || !smooth(*d - *p, *p - *u)) return std::nullopt;
    glm::dvec3 n = glm::cross(*r - *l, *d - *u);
    if (!(glm::length(n) > 0.0)) return std::nullopt;
    n = glm::normalize(n);
    return glm::dot(n, eye - *p) < 0.0 ? -n : n;
}

}  // namespace

const char* normalSpaceName(NormalSpace space) { return space == NormalSpace::Camera ? "camera" : "world"; }

std::string NormalCheck::summary() const {
    if (!performed) return "not performed: " + reason;
    return fmt::format("{} ({} pixels; agreement world/signed {:.3f}, world/packed {:.3f}, camera/signed {:.3f}, "
                       "camera/packed {:.3f})",
                       reason, pixels, agreement[0][0], agreement[0][1], agreement[1][0], agreement[1][1]);
}

NormalCheck checkNormalEncoding(const GBuffer& g, const Camera& camera, const NormalConstraints& fixed) {
    NormalCheck check;
    if (!g.has(Attribute::Normal)) {
        check.reason = "no normal pass";
        return check;
    }
    const Plane& plane = g.planes.at(Attribute::Normal);
    const glm::dmat3 camera_to_world_normals = glm::transpose(glm::dmat3(camera.world_to_camera));
    const glm::dvec3 eye(glm::inverse(camera.world_to_camera)[3]);
    const std::size_t pixels = g.pixelCount();
    const std::size_t step = std::max<std::size_t>(1, pixels / (kMaxSamples * 4));
    double sums[2][2] = {{0, 0}, {0, 0}};
    for (std::size_t i = step / 2; i < pixels && check.pixels < kMaxSamples; i += step) {
        const int x = int(i % std::size_t(g.width)), y = int(i / std::size_t(g.width));
        const auto geometric = geometricNormal(g, camera, eye, x, y);
        if (!geometric) continue;
        const glm::dvec3 stored(plane.at(i, 0), plane.at(i, 1), plane.at(i, 2));
        if (!std::isfinite(stored.x) || !std::isfinite(stored.y) || !std::isfinite(stored.z)) continue;
        for (int packed = 0; packed < 2; ++packed)
            for (int space = 0; space < 2; ++space) {
                glm::dvec3 n = packed ? stored * 2.0 - 1.0 : stored;
                if (space == 1) n = camera_to_world_normals * n;
                const double length = glm::length(n);
                sums[space][packed] += length > 0.0 ? glm::dot(n / length, *geometric) : 0.0;
            }
        ++check.pixels;
    }
    if (check.pixels < 16) {
        check.reason = "too few smooth surface pixels to compare";
        return check;
    }
    check.performed = true;
    // only the readings the caller left open compete (--normals may fix the space or the encoding)
    auto open = [&](int space, int packed) {
        return (!fixed.space || int(*fixed.space == NormalSpace::Camera) == space) &&
               (!fixed.packed || int(*fixed.packed) == packed);
    };
    int best_space = -1, best_packed = -1;
    double runner_up = -2.0;
    for (int space = 0; space < 2; ++space)
        for (int packed = 0; packed < 2; ++packed) {
            check.agreement[space][packed] = sums[space][packed] / double(check.pixels);
            if (open(space, packed) &&
                (best_space < 0 || check.agreement[space][packed] > check.agreement[best_space][best_packed])) {
                best_space = space;
                best_packed = packed;
            }
        }
    for (int space = 0; space < 2; ++space)
        for (int packed = 0; packed < 2; ++packed)
            if (open(space, packed) && (space != best_space || packed != best_packed))
                runner_up = std::max(runner_up, check.agreement[space][packed]);
    const double best = check.agreement[best_space][best_packed];
    const NormalEncoding found{best_space ? NormalSpace::Camera : NormalSpace::World, best_packed == 1};
    const bool as_given = found.space == g.normal_encoding.space && found.packed == g.normal_encoding.packed;
    if (best >= kGoodAgreement && (as_given || best - runner_up >= kMargin)) {
        check.verdict = found;
        check.reason = fmt::format("{} space, {}", normalSpaceName(found.space), found.packed ? "packed" : "signed");
    } else {
        check.reason = fmt::format("no clear fit (best {} space, {}: {:.3f})", normalSpaceName(found.space),
                                   found.packed ? "packed" : "signed", best);
    }
    return check;
}

}  // namespace decalcomp
