#pragma once
// Planar vs radial: which one the depth pass follows, judged against the position pass through the
// camera, over pixels where both are valid (relative errors; median decides, RMS/max reported).
#include <cstddef>
#include <optional>
#include <string>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

struct DepthCheck {
    bool performed = false;
    std::string reason;  // why not, or the verdict in words
    std::size_t pixels = 0;
    double planar_median = 0, planar_rms = 0, planar_max = 0;
    double radial_median = 0, radial_rms = 0, radial_max = 0;
    std::optional<DepthConvention> verdict;  // planar or radial when one fits clearly

    std::string summary() const;  // one line for `info` and composite's report
};
DepthCheck checkDepthConvention(const GBuffer& gbuffer, const Camera& camera);

}  // namespace decalcomp
