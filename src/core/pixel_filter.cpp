#include "decalcomp/pixel_filter.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

struct FilterName {
    PixelFilterType type;
    const char* name;
};
constexpr FilterName kFilterNames[] = {{PixelFilterType::Box, "box"},
                                       {PixelFilterType::Gaussian, "gaussian"},
                                       {PixelFilterType::BlackmanHarris, "blackman-harris"}};

// Strata no wider than this (pixels), and at least kMinTaps per axis: a decal edge crossing a
// stratum is integrated by its soft edge, a wider one would blur it.
constexpr double kMaxStep = 0.5;
constexpr int kMinTaps = 4;
// A stratum at either end holding less than this share of the filter's mass is left out.
constexpr double kNegligible = 0.01;

}  // namespace

double PixelFilter::radius() const {
    switch (type) {
        case PixelFilterType::None: return 0.0;
        case PixelFilterType::Box:
        case PixelFilterType::BlackmanHarris: return 0.5 * width;
        case PixelFilterType::Gaussian: return 0.75 * width;  // 3 sigma
    }
    return 0.0;
}

double PixelFilter::weight1d(double x) const {
    const double r = radius();
    if (!(std::abs(x) <= r)) return 0.0;
    switch (type) {
        case PixelFilterType::None: return 0.0;
        case PixelFilterType::Box: return 1.0;
        case PixelFilterType::Gaussian: {
            const double u = 2.0 * x / width;  // exp(-2 u^2): sigma = width / 4
            return std::exp(-2.0 * u * u);
        }
        case PixelFilterType::BlackmanHarris: {
            const double a = 2.0 * std::numbers::pi * (x / width + 0.5);
            return 0.35875 - 0.48829 * std::cos(a) + 0.14128 * std::cos(2.0 * a) - 0.01168 * std::cos(3.0 * a);
        }
    }
    return 0.0;
}

std::string PixelFilter::spelling() const {
    for (const FilterName& n : kFilterNames)
        if (n.type == type) return fmt::format("{}:{:g}", n.name, width);
    return "none";
}

PixelFilter parsePixelFilter(const std::string& text, const std::string& what) {
    if (text == "none") return {};
    const std::string prefix = what.empty() ? "" : what + ": ";
    const auto colon = text.find(':');
    const std::string name = text.substr(0, colon);
    const auto known = std::find_if(std::begin(kFilterNames), std::end(kFilterNames),
                                    [&](const FilterName& n) { return name == n.name; });
    if (known == std::end(kFilterNames) || colon == std::string::npos)
        throw inputError(fmt::format("{}'{}': expected none or TYPE:WIDTH with TYPE box, gaussian or "
                                     "blackman-harris (e.g. blackman-harris:3)",
                                     prefix, text));
    const std::string number = text.substr(colon + 1);
    double width = 0.0;
    std::size_t used = 0;
    try {
        width = std::stod(number, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != number.size() || !(width > 0.0 && width <= 8.0))
        throw inputError(fmt::format("{}'{}': the width must be a number of pixels in (0, 8]", prefix, text));
    return {known->type, width};
}

namespace {

// Strata no wider than max_step (pixels), min_taps to max_taps of them.
FilterQuadrature stratified(const PixelFilter& filter, double max_step, int min_taps, int max_taps) {
    FilterQuadrature q;
    if (!filter.enabled()) return q;
    const double r = filter.radius();
    const int n = std::clamp(int(std::ceil(2.0 * r / max_step - 1e-9)), min_taps, max_taps);
    q.step = 2.0 * r / n;
    double total = 0.0;
    for (int i = 0; i < n; ++i) {
        const double a = -r + i * q.step;
        // the filter's mass and first moment over the stratum (Simpson on 16 sub-intervals)
        constexpr int kSub = 16;
        double mass = 0.0, moment = 0.0;
        for (int k = 0; k <= kSub; ++k) {
            const double x = a + q.step * k / kSub;
            const double w = ((k == 0 || k == kSub) ? 1.0 : (k % 2 ? 4.0 : 2.0)) * filter.weight1d(x);
            mass += w;
            moment += w * x;
        }
        q.offsets.push_back(mass > 0.0 ? moment / mass : a + 0.5 * q.step);
        q.weights.push_back(mass);
        total += mass;
    }
    for (double& w : q.weights) w /= total;
    // Outer strata the filter barely weighs (Blackman-Harris' tails) cost taps for nothing: drop
    // each end's stratum while it holds less than kNegligible of the mass, and renormalise.
    while (q.offsets.size() > std::size_t(min_taps) && q.weights.front() < kNegligible) {
        const double dropped = q.weights.front() + q.weights.back();
        q.offsets.erase(q.offsets.begin());
        q.offsets.pop_back();
        q.weights.erase(q.weights.begin());
        q.weights.pop_back();
        for (double& w : q.weights) w /= 1.0 - dropped;
    }
    return q;
}

}  // namespace

FilterQuadrature filterQuadrature(const PixelFilter& filter) { return stratified(filter, kMaxStep, kMinTaps, kMaxFilterTaps); }

}  // namespace decalcomp
