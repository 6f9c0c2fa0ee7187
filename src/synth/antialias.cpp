#include "decalcomp/synth_antialias.hpp"

#include <cmath>

#include "decalcomp/error.hpp"

namespace decalcomp::synth {

Plane filterDown(const Plane& fine, int fine_width, int fine_height, int factor, const PixelFilter& filter) {
    if (factor < 1 || fine_width % factor != 0 || fine_height % factor != 0 || !filter.enabled())
        throw Error(ErrorKind::Usage, "filterDown: the fine size must be a multiple of factor, with a filter");
    const int width = fine_width / factor, height = fine_height / factor;
    const double radius = filter.radius();
    // A fine sample's offset from a coarse centre, in coarse pixels, along one axis.
    auto offset = [&](int fine_index, int coarse_index) { return (fine_index + 0.5) / factor - (coarse_index + 0.5); };
    Plane out{fine.components, std::vector<float>(std::size_t(width) * height * fine.components, 0.0f)};
    std::vector<double> sum(std::size_t(fine.components));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            std::fill(sum.begin(), sum.end(), 0.0);
            double total = 0.0;
            const int y0 = std::max(0, int(std::floor((y + 0.5 - radius) * factor))),
                      y1 = std::min(fine_height - 1, int(std::ceil((y + 0.5 + radius) * factor)));
            const int x0 = std::max(0, int(std::floor((x + 0.5 - radius) * factor))),
                      x1 = std::min(fine_width - 1, int(std::ceil((x + 0.5 + radius) * factor)));
            for (int fy = y0; fy <= y1; ++fy) {
                const double wy = filter.weight1d(offset(fy, y));
                if (wy <= 0.0) continue;
                for (int fx = x0; fx <= x1; ++fx) {
                    const double w = wy * filter.weight1d(offset(fx, x));
                    if (w <= 0.0) continue;
                    const std::size_t i = std::size_t(fy) * fine_width + fx;
                    for (int c = 0; c < fine.components; ++c) sum[std::size_t(c)] += w * fine.at(i, c);
                    total += w;
                }
            }
            const std::size_t o = std::size_t(y) * width + x;
            for (int c = 0; c < fine.components; ++c) out.at(o, c) = float(sum[std::size_t(c)] / total);
        }
    return out;
}

GBuffer filterDown(const GBuffer& fine, int factor, const PixelFilter& filter) {
    if (fine.origin_x != 0 || fine.origin_y != 0 || fine.display_width != fine.width ||
        fine.display_height != fine.height)
        throw Error(ErrorKind::Usage, "filterDown: full frames only");
    GBuffer out = fine;
    out.width = out.display_width = fine.width / factor;
    out.height = out.display_height = fine.height / factor;
    out.pixel_filter = filter;
    for (auto& [attribute, plane] : out.planes) plane = filterDown(fine.planes.at(attribute), fine.width, fine.height, factor, filter);
    for (std::size_t m = 0; m < out.mask_weights.size(); ++m)
        out.mask_weights[m] = filterDown(fine.mask_weights[m], fine.width, fine.height, factor, filter);
    return out;
}

}  // namespace decalcomp::synth
