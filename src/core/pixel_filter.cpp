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
        if (n.type == type) return fmt::format("{}:{:g}{}", n.name, width, fast ? ":fast" : "");
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
        throw inputError(fmt::format("{}'{}': expected none or TYPE:WIDTH[:fast] with TYPE box, gaussian or "
                                     "blackman-harris (e.g. blackman-harris:3)",
                                     prefix, text));
    std::string number = text.substr(colon + 1);
    const bool fast = number.ends_with(":fast");
    if (fast) number.resize(number.size() - 5);
    double width = 0.0;
    std::size_t used = 0;
    try {
        width = std::stod(number, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != number.size() || !(width > 0.0 && width <= 8.0))
        throw inputError(fmt::format("{}'{}': the width must be a number of pixels in (0, 8]", prefix, text));
    return {known->type, width, fast};
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

namespace {

// The 1D filter's cumulative share at kCdfSteps + 1 points across [-radius, radius] (midpoint sums).
constexpr int kCdfSteps = 2048;
std::vector<double> cumulative(const PixelFilter& filter) {
    const double r = filter.radius(), h = 2.0 * r / kCdfSteps;
    std::vector<double> cdf(kCdfSteps + 1, 0.0);
    for (int k = 0; k < kCdfSteps; ++k) cdf[std::size_t(k) + 1] = cdf[std::size_t(k)] + filter.weight1d(-r + (k + 0.5) * h);
    for (double& c : cdf) c /= cdf.back();
    return cdf;
}

double cdfAt(const std::vector<double>& cdf, double radius, double x) {
    const double t = (x + radius) / (2.0 * radius) * kCdfSteps;
    if (!(t > 0.0)) return 0.0;
    if (!(t < kCdfSteps)) return 1.0;
    const auto k = std::size_t(t);
    return cdf[k] + (cdf[k + 1] - cdf[k]) * (t - double(k));
}

// P(nx X + ny Y <= d) for X, Y independent under the filter: the integral over Y of the filter's
// weight times X's cumulative share below the edge.
double edgeSpreadWith(const PixelFilter& filter, const std::vector<double>& cdf, double nx, double ny, double d) {
    const double r = filter.radius();
    double a = std::abs(nx), b = std::abs(ny);
    if (a < b) std::swap(a, b);  // the filter is the same on both axes and on either side
    if (!(a > 0.0)) return d >= 0.0 ? 1.0 : 0.0;
    const double h = 2.0 * r / kCdfSteps;
    double sum = 0.0;
    for (int k = 0; k < kCdfSteps; ++k) {
        const double y = -r + (k + 0.5) * h;
        sum += (cdf[std::size_t(k) + 1] - cdf[std::size_t(k)]) * cdfAt(cdf, r, (d - b * y) / a);
    }
    return sum;
}

}  // namespace

double edgeSpread(const PixelFilter& filter, double nx, double ny, double d) {
    if (!filter.enabled()) return d >= 0.0 ? 1.0 : 0.0;
    return edgeSpreadWith(filter, cumulative(filter), nx, ny, d);
}

std::vector<double> edgeSpreadTable(const PixelFilter& filter) {
    std::vector<double> table(std::size_t(kEdgeSpreadRatios) * kEdgeSpreadSteps, 1.0);
    if (!filter.enabled()) return table;
    const std::vector<double> cdf = cumulative(filter);
    for (int k = 0; k < kEdgeSpreadRatios; ++k) {
        const double ratio = double(k) / (kEdgeSpreadRatios - 1), norm = std::sqrt(1.0 + ratio * ratio);
        const double nx = 1.0 / norm, ny = ratio / norm, support = filter.radius() * (nx + ny);
        for (int j = 0; j < kEdgeSpreadSteps; ++j)
            table[std::size_t(k) * kEdgeSpreadSteps + std::size_t(j)] =
                edgeSpreadWith(filter, cdf, nx, ny, support * j / (kEdgeSpreadSteps - 1));
    }
    return table;
}

double edgeSpreadFromTable(const std::vector<double>& table, double radius, double gu, double gv, double delta) {
    const double a = std::max(std::abs(gu), std::abs(gv)), b = std::min(std::abs(gu), std::abs(gv));
    // delta / |g| pixels from the centre, over the support radius (|nx| + |ny|) along g
    const double t = delta / (radius * (a + b));
    if (!(std::abs(t) < 1.0)) return t > 0.0 ? 1.0 : 0.0;  // also a flat quantity (a = 0): the hard test
    const double rk = b / a * (kEdgeSpreadRatios - 1), sj = std::abs(t) * (kEdgeSpreadSteps - 1);
    const int k = std::min(int(rk), kEdgeSpreadRatios - 2), j = std::min(int(sj), kEdgeSpreadSteps - 2);
    const double fk = rk - k, fj = sj - j;
    auto at = [&](int kk, int jj) { return table[std::size_t(kk) * kEdgeSpreadSteps + std::size_t(jj)]; };
    const double e = (at(k, j) * (1 - fj) + at(k, j + 1) * fj) * (1 - fk) + (at(k + 1, j) * (1 - fj) + at(k + 1, j + 1) * fj) * fk;
    return t >= 0.0 ? e : 1.0 - e;
}

double equivalentBoxWidth(const PixelFilter& filter) {
    if (!filter.enabled()) return 0.0;
    const double r = filter.radius(), h = 2.0 * r / kCdfSteps;
    double mass = 0.0, second = 0.0;
    for (int k = 0; k < kCdfSteps; ++k) {
        const double x = -r + (k + 0.5) * h, w = filter.weight1d(x);
        mass += w;
        second += w * x * x;
    }
    return std::sqrt(12.0 * second / mass);
}

}  // namespace decalcomp
