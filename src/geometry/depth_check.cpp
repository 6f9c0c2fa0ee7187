// checkDepthConvention: planar vs radial depth against the position pass through a camera.
#include "decalcomp/depth_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "decalcomp/geometry.hpp"
#include "geometry/median.hpp"

namespace decalcomp {

std::string DepthCheck::summary() const {
    if (!performed) return "not checked (" + reason + ")";
    return fmt::format("{}; relative error planar median {:.3g} (RMS {:.3g}, max {:.3g}), radial median {:.3g} "
                       "(RMS {:.3g}, max {:.3g}) over {} pixels",
                       reason, planar_median, planar_rms, planar_max, radial_median, radial_rms, radial_max, pixels);
}

DepthCheck checkDepthConvention(const GBuffer& g, const Camera& camera) {
    DepthCheck check;
    if (!g.has(Attribute::Depth) || !g.has(Attribute::Position)) {
        check.reason = "needs a depth and a position pass";
        return check;
    }
    if (g.depth_convention != DepthConvention::Planar && g.depth_convention != DepthConvention::Radial) {
        check.reason = fmt::format("the depth convention is {}", depthConventionName(g.depth_convention));
        return check;
    }
    if (camera.isOrthographic()) {
        check.reason = "orthographic camera: planar and radial depth are the same";
        return check;
    }
    const Plane& depth = g.planes.at(Attribute::Depth);
    const Plane& position = g.planes.at(Attribute::Position);
    std::vector<double> planar, radial;
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        if (!isGeometryPixel(g, i)) continue;
        const glm::dvec3 world(position.at(i, 0), position.at(i, 1), position.at(i, 2));
        if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) continue;
        const glm::dvec3 c(camera.world_to_camera * glm::dvec4(world, 1.0));
        const double d = depth.at(i, 0), p = -c.z, r = glm::length(c);
        if (!(p > 0.0)) continue;
        planar.push_back(std::abs(d - p) / p);
        radial.push_back(std::abs(d - r) / r);
    }
    check.pixels = planar.size();
    if (planar.empty()) {
        check.reason = "no pixel with both depth and position in front of the camera";
        return check;
    }
    check.performed = true;
    auto summarise = [](const std::vector<double>& e, double& med, double& rms, double& max) {
        double sum = 0.0;
        for (double v : e) {
            sum += v * v;
            max = std::max(max, v);
        }
        rms = std::sqrt(sum / double(e.size()));
        med = geometry::median(e);
    };
    summarise(planar, check.planar_median, check.planar_rms, check.planar_max);
    summarise(radial, check.radial_median, check.radial_rms, check.radial_max);
    const double best = std::min(check.planar_median, check.radial_median);
    const double other = std::max(check.planar_median, check.radial_median);
    if (best < 1e-3 && other > 4.0 * best + 1e-5) {
        check.verdict = check.planar_median <= check.radial_median ? DepthConvention::Planar : DepthConvention::Radial;
        check.reason = fmt::format("{} (the depth pass matches the position pass)", depthConventionName(*check.verdict));
    } else if (best < 1e-3) {
        check.reason = "undecided: planar and radial fit equally (narrow field of view?)";
    } else {
        check.reason = "neither planar nor radial matches the position pass (ndc depth? pass --depth)";
    }
    return check;
}

}  // namespace decalcomp
