#pragma once
// The pixel filter's closed form in the reference (PixelFilter::fast), in double precision: it
// mirrors kernels/filter_integral.h (dc_integrated_decal). reference::shade (reference.cpp) takes
// each decal once per pixel on one tangent plane through it instead of the filter's taps.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/decal.hpp"
#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/reference.hpp"
#include "reference/decal_hit.hpp"

namespace decalcomp::reference {

// The closed form of a decal over the pixel filter on one tangent plane (PixelFilter::fast;
// kernels/filter_integral.h): the filter's edge-spread shares of straight edges of quantities
// that change linearly with the pixel offset (u, v).
struct EdgeSpreads {
    std::vector<double> table;
    double radius = 0.0;
    // the share where a <= a0 + delta, a changing by g per pixel offset
    double share(glm::dvec2 g, double delta) const { return edgeSpreadFromTable(table, radius, g.x, g.y, delta); }
    // the share where lo <= a <= hi; `ambiguous` set where an edge is steeper than rounding
    // (`slack` in a's measure) and lies within the footprint's reach of a0 plus that slack
    double slab(double a0, glm::dvec2 g, double lo, double hi, double slack, bool& ambiguous) const {
        const double reach = radius * (std::abs(g.x) + std::abs(g.y));
        if (slack > 0.05 * reach && (std::abs(lo - a0) <= reach + slack || std::abs(hi - a0) <= reach + slack))
            ambiguous = true;
        return std::max(0.0, share(g, hi - a0) - share(g, lo - a0));
    }
};

// What the closed form takes of a frame's pixel filter: its edge-spread shares (empty unless the
// filter is fast), the width of its equivalent box (the texture read that stands for a tap's
// stratum) and the quadrature's step (the footprint's reach, as the kernels bound it).
struct FilterIntegral {
    EdgeSpreads edge_spreads;
    double box_width = 0.0;
    double quadrature_step = 0.0;
};
FilterIntegral filterIntegral(const PixelFilter& filter, const FilterQuadrature& quadrature);

// Decal `decal` at pixel point P in closed form over the filter on the tangent plane that moves by
// du, dv (world) per pixel offset (dc_integrated_decal up to the texture reads). `slack`: how far
// rounding may move a local coordinate; `scale`: world_to_local's largest row norm (the measure
// `slack` is taken in).
struct IntegratedDecalHit {
    // hit.fade 0 where the decal misses the footprint or where the kernels pass over it (the
    // footprint's bounding sphere misses its volume); hit.ambiguous where rounding may flip either
    DecalHit hit;
    glm::dvec3 axis_slack{0.0};  // how far rounding moves each local coordinate
};
IntegratedDecalHit integratedDecalHit(const FilterIntegral& filter, const Decal& decal,
                                      const glm::dmat4& world_to_local, double scale, const glm::dvec3& P,
                                      const std::optional<glm::dvec3>& normal, const glm::dvec3& du,
                                      const glm::dvec3& dv, double slack);

// The decal's textures over the filter at a hit of integratedDecalHit: texel by texel where the
// texels carry the decal's sides (and on nearest cube faces), else one read over the filter's
// equivalent box; `ambiguous` set where a read lies within rounding of a step.
DecalValues integratedDecalValues(const FilterIntegral& filter, const Decal& decal, const IntegratedDecalHit& at,
                                  double slack, const std::vector<Texture2D>& textures,
                                  const std::vector<std::vector<Texture2D>>& chains, bool& ambiguous);

}  // namespace decalcomp::reference
