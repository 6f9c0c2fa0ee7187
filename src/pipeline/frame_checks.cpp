// Warnings for frames that would composite to nothing, or to less than the user expects.
#include <fmt/format.h>

#include <cmath>

#include "decalcomp/geometry.hpp"
#include "decalcomp/pipeline.hpp"

namespace decalcomp {

namespace {

struct DepthCensus {
    std::size_t pixels = 0, geometry = 0, nan = 0, negative = 0, beyond_far = 0;
};

DepthCensus censusOf(const GBuffer& gbuffer, const Camera& camera) {
    DepthCensus census;
    census.pixels = std::size_t(gbuffer.width) * std::size_t(gbuffer.height);
    if (!gbuffer.has(Attribute::Depth)) {  // the position pass carries the geometry
        for (std::size_t i = 0; i < census.pixels; ++i) census.geometry += isGeometryPixel(gbuffer, i);
        return census;
    }
    const std::vector<float>& depth = gbuffer.planes.at(Attribute::Depth).samples;  // one component
    const double far = camera.farPlane();
    const bool planar_limit = gbuffer.depth_convention == DepthConvention::Planar && std::isfinite(far);
    for (std::size_t i = 0; i < census.pixels; ++i) {
        const float d = depth[i];
        census.nan += std::isnan(d);
        census.negative += d < 0.0f;
        if (planar_limit && d > far && std::isfinite(d) && d < kBackgroundDepth) ++census.beyond_far;
        else census.geometry += !isBackgroundDepth(gbuffer.depth_convention, gbuffer.reversed_z, d);
    }
    return census;
}

}  // namespace

std::vector<std::string> depthWarnings(const GBuffer& gbuffer, const Camera& camera, const std::string& depth_channel,
                                       const std::string& label) {
    const DepthCensus census = censusOf(gbuffer, camera);
    const std::string field = depth_channel.empty() ? "depth" : fmt::format("depth ({})", depth_channel);
    std::vector<std::string> warnings;
    if (census.pixels > 0 && census.geometry == 0) {
        warnings.push_back(fmt::format(
            "{}: {}: every pixel is background ({} NaN, {} negative, {} beyond the camera's far plane {:.6g}), so no "
            "decal can land; check --depth (planar, radial, ndc, position), --reversed-z and the camera",
            label, field, census.nan, census.negative, census.beyond_far, camera.farPlane()));
        return warnings;
    }
    if (census.nan > 0)
        warnings.push_back(fmt::format("{}: {}: {} of {} pixels hold NaN depth; they are background (no decal)", label,
                                       field, census.nan, census.pixels));
    if (census.negative > 0)
        warnings.push_back(fmt::format("{}: {}: {} of {} pixels hold negative depth; they are background (no decal); "
                                       "if the renderer writes camera z (negative in front), negate it",
                                       label, field, census.negative, census.pixels));
    return warnings;
}

}  // namespace decalcomp
