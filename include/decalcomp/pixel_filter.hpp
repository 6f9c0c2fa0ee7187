#pragma once
// The renderer's pixel filter (docs/pixel-filter.md): every pass of an antialiased render is a
// filtered average over each pixel's footprint, so decals are integrated over the same filter.
#include <optional>
#include <string>
#include <vector>

namespace decalcomp {

enum class PixelFilterType { None, Box, Gaussian, BlackmanHarris };

// A separable filter: weight(x, y) = weight1d(x) * weight1d(y), x and y in pixels from the centre.
// `width` is the filter's nominal width in pixels: the full support for box and Blackman-Harris,
// 4 standard deviations for the Gaussian (RenderMan's and Cycles' convention; evaluated out to 3
// sigma). Cycles doubles its Blackman-Harris "Filter Size": Blender's default 1.5 px is
// blackman-harris:3 here.
struct PixelFilter {
    PixelFilterType type = PixelFilterType::None;
    double width = 0.0;
    // How decals are integrated over it (docs/pixel-filter.md): false, taps on the pixel's tangent
    // plane stacking the decals per tap; true ("fast"), each decal in closed form on that plane
    // (edge-spread shares, nearest texels weighted one by one), about 4x faster and less exact.
    bool fast = false;

    bool enabled() const { return type != PixelFilterType::None; }
    double radius() const;                 // support half-width in pixels (0 for none)
    double weight1d(double x) const;       // unnormalised
    std::string spelling() const;          // "none", "box:1", "gaussian:2", "blackman-harris:3:fast"
    bool operator==(const PixelFilter& other) const {
        return type == other.type && width == other.width && fast == other.fast;
    }
};

// "none", or TYPE:WIDTH[:fast] with TYPE box|gaussian|blackman-harris and 0 < WIDTH <= 8. Throws
// Error(Input) naming `what` (the option or field; may be empty) for anything else.
PixelFilter parsePixelFilter(const std::string& text, const std::string& what);

// The 1D quadrature the kernels integrate with: [-radius, radius] cut into strata `step` pixels
// wide (at most 0.5 px, 4 to kMaxFilterTaps of them), one tap per stratum at its centroid under
// the filter, weighted by the filter's integral over it (normalised to sum 1). 2D taps are the
// products. Each tap prefilters its stratum (soft decal edges, texture lookups of the stratum's
// size), so a few taps integrate steps accurately.
struct FilterQuadrature {
    std::vector<double> offsets, weights;
    double step = 0.0;
};
inline constexpr int kMaxFilterTaps = 8;
FilterQuadrature filterQuadrature(const PixelFilter& filter);

// The filter's edge-spread function (docs/pixel-filter.md "Integrated evaluation"): the share of
// its weight on the side n . x <= d of a straight edge through the footprint, n a unit normal.
// exact: by numerical integration of the separable filter. The kernels interpolate a table of it:
// kEdgeSpreadRatios rows for the ratio min(|nx|, |ny|) / max(|nx|, |ny|) from 0 to 1, each
// kEdgeSpreadSteps values of d from 0 to the filter's support along n, radius (|nx| + |ny|)
// (d < 0 gives 1 - E(-d)).
inline constexpr int kEdgeSpreadRatios = 9, kEdgeSpreadSteps = 33;
double edgeSpread(const PixelFilter& filter, double nx, double ny, double d);
std::vector<double> edgeSpreadTable(const PixelFilter& filter);  // [ratio * kEdgeSpreadSteps + step]
// The table interpolated as the kernels do (dc_edge_spread): the share on the side a <= a0 + delta
// of a quantity a whose change per pixel offset (u, v) is (gu, gv).
double edgeSpreadFromTable(const std::vector<double>& table, double radius, double gu, double gv, double delta);
// The width of the box with the filter's variance: what one texture read integrates where texels
// cannot be weighted one by one.
double equivalentBoxWidth(const PixelFilter& filter);

// Pixels beyond a decal's projection that filtering can change or read: the widest filter's
// radius (gaussian:8, 6 px), half a stratum and the neighbour the mixed-pixel test reads.
inline constexpr int kMaxFilterReach = 8;

// The filter a frame is composited with, and why (docs/pixel-filter.md "Choosing").
struct PixelFilterChoice {
    PixelFilter filter;
    std::string source;  // "--pixel-filter", "header pixelFilter of F", "profile blender", ...
    // False where the frame could not tell (no normal pass, or one without a sharp turn) and the
    // profile's default stands in: a sequence waits for a frame that can tell.
    bool conclusive = true;
};

}  // namespace decalcomp
