// The pixel filter's closed form in the reference (filter_integral.hpp): mirrors
// kernels/filter_integral.h.
#include "reference/filter_integral.hpp"

#include <algorithm>
#include <cmath>

namespace decalcomp::reference {

namespace {

// Texels per axis an integrated read weights one by one; wider footprints read a coarser level
// (DC_INTEGRATED_TEXELS in kernels/filter_integral.h: keep the two equal).
constexpr int kIntegratedTexels = 12;

// Whether the decal's texels carry its side edges (dc_texel_edges): box and frustum decals with
// nearest 2D textures.
bool texelEdges(const Decal& d) {
    return (d.kind == DecalKind::Box || d.kind == DecalKind::Frustum) && d.filter == TextureFilter::Nearest &&
           (d.albedo_texture >= 0 || d.normal_texture >= 0 || d.orm_texture >= 0 || d.emission_texture >= 0);
}

// The filter's share of each texel column [i, i + 1) that the texel coordinate c0 + g . (u, v)
// crosses (dc_texel_span): the first column and the shares. `slack` in texels.
int texelShares(const EdgeSpreads& e, double c0, glm::dvec2 g, int size, double slack, std::vector<double>& shares,
                bool& ambiguous) {
    const double reach = e.radius * (std::abs(g.x) + std::abs(g.y));
    const double lo = std::clamp(c0 - reach, 0.0, double(size) - 1.0),
                 hi = std::clamp(c0 + reach, 0.0, double(size) - 1.0);
    const int i0 = int(std::floor(lo));
    const int i1 = std::min(int(std::floor(hi)), i0 + kIntegratedTexels - 1);
    // the window's ends matter only where it is cut short: a texel past either end of the
    // footprint has no share
    auto nearInteger = [&](double x) { return std::abs(x - std::round(x)) <= slack; };
    if (int(std::floor(hi)) >= i0 + kIntegratedTexels - 1 && (nearInteger(lo) || nearInteger(hi))) ambiguous = true;
    shares.clear();
    double below = e.share(g, double(i0) - c0);
    for (int i = i0; i <= i1; ++i) {
        const double next = e.share(g, double(i + 1) - c0);
        shares.push_back(next - below);
        below = next;
    }
    return i0;
}

// A nearest 2D texture integrated over the filter (dc_integrate_slice): coordinates st with steps
// su, sv per pixel offset; zero beyond the texture's edges. `slack` in texture coordinates.
glm::dvec4 integrateSlice(const EdgeSpreads& e, const std::vector<Texture2D>& chain, glm::dvec2 st, glm::dvec2 su,
                          glm::dvec2 sv, long slice, double slack, bool& ambiguous) {
    const Texture2D& base = chain[0];
    const double span0 =
        2.0 * e.radius *
        std::max((std::abs(su.x) + std::abs(sv.x)) * base.width, (std::abs(su.y) + std::abs(sv.y)) * base.height);
    double span = span0;
    std::size_t level = 0;
    const double threshold = kIntegratedTexels - 1;
    while (span > threshold && level + 1 < chain.size()) {
        if (std::abs(span - threshold) <= 1e-4 * threshold) ambiguous = true;  // the level choice is a step
        span *= 0.5;
        ++level;
    }
    if (level + 1 < chain.size() && std::abs(span - threshold) <= 1e-4 * threshold) ambiguous = true;
    const Texture2D& t = chain[level];
    std::vector<double> share_s, share_t;
    const int i0 = texelShares(e, st.x * t.width, glm::dvec2(su.x, sv.x) * double(t.width), t.width,
                               slack * t.width + 1e-5 * t.width, share_s, ambiguous);
    const int j0 = texelShares(e, st.y * t.height, glm::dvec2(su.y, sv.y) * double(t.height), t.height,
                               slack * t.height + 1e-5 * t.height, share_t, ambiguous);
    glm::dvec4 sum(0.0);
    for (std::size_t j = 0; j < share_t.size(); ++j) {
        if (!(share_t[j] > 0.0)) continue;
        glm::dvec4 row(0.0);
        for (std::size_t i = 0; i < share_s.size(); ++i)
            row += texelAt(t, long(i0) + long(i), long(j0) + long(j), slice) * share_s[i];
        sum += row * share_t[j];
    }
    return sum;
}

// How far the footprint's bounding sphere (world radius `radius` around local point l) stays
// outside the decal's volume, in local units (dc_filter_may_reach_at; <= 0: it may reach).
double footprintReach(const Decal& decal, const glm::dmat4& world_to_local, const glm::dvec3& l, double radius) {
    glm::dvec3 reach;
    for (int r = 0; r < 3; ++r)
        reach[r] = radius * glm::length(glm::dvec3(world_to_local[0][r], world_to_local[1][r], world_to_local[2][r]));
    if (decal.kind == DecalKind::Box || decal.kind == DecalKind::Volume)
        return std::max({std::abs(l.x) - reach.x, std::abs(l.y) - reach.y, std::abs(l.z) - reach.z}) - 0.5;
    const double r = std::max({reach.x, reach.y, reach.z});
    if (decal.kind == DecalKind::Cube) return glm::length(l) - r - 0.5;
    const double dist = -l.z, half_h = (dist + r) * std::tan(glm::radians(decal.fov_y_deg) / 2.0);
    return std::max({decal.near - (dist + r), dist - r - decal.far, std::abs(l.x) - r - half_h * decal.aspect,
                     std::abs(l.y) - r - half_h});
}

// Decal `decal` integrated over the filter on the tangent plane through P with normal n
// (dc_decal_lookup_integrated): local point l of P moving by lu, lv per pixel offset. Side edges
// that texels carry are left to the texture reads; the other faces cover their edge-spread share;
// fades are taken at the centre. The hit's local_dx/dy are l + lu, l + lv.
DecalHit integratedHit(const Decal& decal, const glm::dmat4& world_to_local, const glm::dvec3& P,
                       const std::optional<glm::dvec3>& normal, const glm::dvec3& lu, const glm::dvec3& lv,
                       const EdgeSpreads& e, double slack, const glm::dvec3& axis_slack) {
    DecalHit out;
    const glm::dvec3 l(world_to_local * glm::dvec4(P, 1.0));
    out.local = l;
    out.local_dx = l + lu;
    out.local_dy = l + lv;
    out.footprint = out.filtered = true;
    const bool texel_edges = texelEdges(decal);
    const glm::dmat3 axes(decal.world_matrix);
    out.right = axes[0];
    out.up = axes[1];
    bool& a = out.ambiguous;
    double fade = 1.0;
    switch (decal.kind) {
        case DecalKind::Box:
        case DecalKind::Volume: {
            fade = e.slab(l.z, {lu.z, lv.z}, -0.5, 0.5, axis_slack.z, a);
            if (!texel_edges)
                fade *= e.slab(l.x, {lu.x, lv.x}, -0.5, 0.5, axis_slack.x, a) *
                        e.slab(l.y, {lu.y, lv.y}, -0.5, 0.5, axis_slack.y, a);
            if (!(fade > 0.0)) return out;
            if (decal.axis_fade > 0.0) fade *= std::clamp((0.5 - std::abs(l.z)) / (0.5 * decal.axis_fade), 0.0, 1.0);
            out.facing = glm::normalize(glm::dvec3(decal.world_matrix[2]));
            break;
        }
        case DecalKind::Frustum: {
            const double dist = -l.z;
            const double edge_slack = 2.0 * slack;  // both sides of each comparison carry rounding
            if (std::abs(dist) <= edge_slack) a = true;
            if (!(dist > 0.0)) return out;
            fade = e.slab(dist, {-lu.z, -lv.z}, decal.near, decal.far, edge_slack, a);
            if (!(fade > 0.0)) return out;
            if (decal.distance_fade[1] > 0.0) fade *= rampDown(dist, decal.distance_fade[0], decal.distance_fade[1]);
            out.facing = glm::normalize(glm::dvec3(decal.world_matrix[3]) - P);
            if (!texel_edges) {
                const double tan_half = std::tan(glm::radians(decal.fov_y_deg) / 2.0);
                auto st = [&](const glm::dvec3& v) {
                    const double hh = -v.z * tan_half;
                    return glm::dvec2(0.5 + v.x / (2.0 * hh * decal.aspect), 0.5 - v.y / (2.0 * hh));
                };
                const glm::dvec2 c = st(l), su = st(l + lu) - c, sv = st(l + lv) - c;
                const double half_h = dist * tan_half, half_w = half_h * decal.aspect;
                fade *= e.slab(c.x, {su.x, sv.x}, 0.0, 1.0, 2.0 * edge_slack / half_w, a) *
                        e.slab(c.y, {su.y, sv.y}, 0.0, 1.0, 2.0 * edge_slack / half_h, a);
            }
            break;
        }
        case DecalKind::Cube: {
            const double r = glm::length(l);
            a = std::abs(r - 0.5) <= slack;
            if (!(r <= 0.5) || !(r > 0.0)) return out;
            fade = std::clamp(1.0 - r / 0.5, 0.0, 1.0);
            cubeFaceAt(decal, l, P, slack, out);
            break;
        }
    }
    if (normal && decal.angle_fade_deg[1] > 0.0) {
        const double cosine = glm::dot(*normal, out.facing);
        if (std::abs(cosine) <= 1e-4) a = true;  // the back-face cut is a step
        fade *= cosine <= 0.0 ? 0.0
                              : rampDown(std::acos(std::min(cosine, 1.0)), glm::radians(decal.angle_fade_deg[0]),
                                         glm::radians(decal.angle_fade_deg[1]));
    }
    out.fade = fade;
    return out;
}

}  // namespace

FilterIntegral filterIntegral(const PixelFilter& filter, const FilterQuadrature& quadrature) {
    FilterIntegral out;
    out.box_width = equivalentBoxWidth(filter);
    out.quadrature_step = quadrature.step;
    if (filter.enabled() && filter.fast) {
        out.edge_spreads.table = edgeSpreadTable(filter);
        out.edge_spreads.radius = filter.radius();
    }
    return out;
}

IntegratedDecalHit integratedDecalHit(const FilterIntegral& filter, const Decal& decal,
                                      const glm::dmat4& world_to_local, double scale, const glm::dvec3& P,
                                      const std::optional<glm::dvec3>& normal, const glm::dvec3& du,
                                      const glm::dvec3& dv, double slack) {
    IntegratedDecalHit out;
    const glm::dmat3 to_local(world_to_local);
    const glm::dvec3 lu = to_local * du, lv = to_local * dv;
    // rounding moves each local coordinate by its row of world_to_local
    for (int r = 0; r < 3; ++r) {
        const glm::dmat4& w = world_to_local;
        out.axis_slack[r] = slack * (std::abs(w[0][r]) + std::abs(w[1][r]) + std::abs(w[2][r])) / scale;
    }
    DecalHit& hit = out.hit;
    hit = integratedHit(decal, world_to_local, P, normal, lu, lv, filter.edge_spreads, slack, out.axis_slack);
    // the kernels pass over decals whose volume the footprint's bounding sphere misses
    // (dc_filter_may_reach_at), where the linear map reaches further than the projective one
    const double radius =
        (1.25 * filter.edge_spreads.radius + 0.5 * filter.quadrature_step) * (glm::length(du) + glm::length(dv));
    if (hit.fade > 0.0) {
        const double cut = footprintReach(decal, world_to_local, hit.local, radius);
        if (std::abs(cut) <= 1e-4 * (1.0 + glm::length(hit.local))) hit.ambiguous = true;
        if (cut > 0.0) hit.fade = 0.0;
    }
    return out;
}

DecalValues integratedDecalValues(const FilterIntegral& filter, const Decal& decal, const IntegratedDecalHit& at,
                                  double slack, const std::vector<Texture2D>& textures,
                                  const std::vector<std::vector<Texture2D>>& chains, bool& ambiguous) {
    const DecalHit& hit = at.hit;
    const bool cube_face = decal.kind == DecalKind::Cube && decal.filter == TextureFilter::Nearest;
    if (texelEdges(decal) || cube_face) {
        // texel by texel: the texture's edges are the decal's sides (and nearest cube faces)
        const double tan_half = std::tan(glm::radians(decal.fov_y_deg) / 2.0);
        const int face = hit.cube.face;
        auto st_of = [&](const glm::dvec3& v) {
            if (decal.kind == DecalKind::Box) return glm::dvec2(v.x + 0.5, 0.5 - v.y);
            if (cube_face) {  // on the face of the centre, even past its edge
                const double ma[6] = {v.x, -v.x, v.y, -v.y, v.z, -v.z};
                const double sc[6] = {-v.z, v.z, v.x, v.x, v.x, -v.x};
                const double tc[6] = {-v.y, -v.y, v.z, -v.z, -v.y, -v.y};
                return glm::dvec2(0.5 * (sc[face] / ma[face] + 1.0), 0.5 * (tc[face] / ma[face] + 1.0));
            }
            const double hh = -v.z * tan_half;
            return glm::dvec2(0.5 + v.x / (2.0 * hh * decal.aspect), 0.5 - v.y / (2.0 * hh));
        };
        const glm::dvec2 st = st_of(hit.local), su = st_of(hit.local_dx) - st, sv = st_of(hit.local_dy) - st;
        // how far rounding moves the texture coordinates (s, t)
        const double st_slack = decal.kind == DecalKind::Box ? 2.0 * std::max(at.axis_slack.x, at.axis_slack.y)
                                : cube_face                  ? hit.direction_slack
                                            : 4.0 * slack / (-hit.local.z * tan_half * std::min(1.0, decal.aspect));
        return valuesAtHit(decal, hit, [&](std::size_t texture) {
            return integrateSlice(filter.edge_spreads, chains[texture], st, su, sv, cube_face ? face : 0, st_slack,
                                  ambiguous);
        });
    }
    // one read over the filter's equivalent box, as a tap reads its stratum
    return valuesAtHit(decal, hit, [&](std::size_t texture) {
        return hitTexelScaled(hit, decal, textures[texture], chains[texture], slack, ambiguous, filter.box_width);
    });
}

}  // namespace decalcomp::reference
