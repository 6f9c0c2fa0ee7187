#include "pipeline/frame_pixel_filter.hpp"

#include <algorithm>
#include <cmath>

#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>
#include <glm/glm.hpp>

#include "decalcomp/profiles.hpp"

namespace decalcomp {

namespace {

// Evidence in the normal pass: neighbours whose normals turn by more than 30 degrees (edges),
// and normals shorter than 0.99 (averages of differing directions). A filter averages normals
// across every crease and silhouette, leaving bands of short normals along each edge; an
// unfiltered frame has sharp turns with at most a few short normals (Cycles' 0.01 px filter
// mixes a few dozen edge pixels). Background (zero) normals and chunks a frame does not decode
// (zeros) do not count.
struct NormalEdges {
    std::size_t sharp_turns = 0, short_normals = 0;
    // hard edges: sharp turns, and fewer short normals than a tenth of them
    bool hard() const { return sharp_turns > 0 && short_normals * 10 < sharp_turns; }
};

NormalEdges normalEdges(const GBuffer& gbuffer) {
    NormalEdges e;
    const auto found = gbuffer.planes.find(Attribute::Normal);
    if (found == gbuffer.planes.end() || found->second.components != 3) return e;
    const Plane& plane = found->second;
    const auto normal = [&](std::size_t i) {
        glm::dvec3 n(plane.at(i, 0), plane.at(i, 1), plane.at(i, 2));
        return gbuffer.normal_encoding.packed ? 2.0 * n - 1.0 : n;
    };
    const auto valid = [](const glm::dvec3& n) { return glm::length(n) > 0.5; };
    for (int y = 0; y < gbuffer.height; ++y)
        for (int x = 0; x < gbuffer.width; ++x) {
            const std::size_t i = std::size_t(y) * gbuffer.width + x;
            const glm::dvec3 n = normal(i);
            if (!valid(n)) continue;
            if (glm::length(n) < 0.99) ++e.short_normals;
            const auto turns = [&](std::size_t j) {
                const glm::dvec3 m = normal(j);
                return valid(m) && glm::dot(n, m) < 0.866 * glm::length(n) * glm::length(m);
            };
            if (x + 1 < gbuffer.width && turns(i + 1)) ++e.sharp_turns;
            if (y + 1 < gbuffer.height && turns(i + std::size_t(gbuffer.width))) ++e.sharp_turns;
        }
    return e;
}

}  // namespace

PixelFilterChoice choosePixelFilter(const std::vector<ExrImage>& files, const std::string& profile,
                                    const std::vector<std::string>& profile_files, const GBuffer& gbuffer,
                                    const std::optional<PixelFilter>& requested) {
    if (requested) return {*requested, "--pixel-filter"};
    for (const ExrImage& file : files)
        for (const ExrPart& part : file.parts)
            if (const auto* text = part.header.findTypedAttribute<Imf::StringAttribute>("pixelFilter"))
                return {parsePixelFilter(text->value(), file.path + ": header pixelFilter"),
                        "header pixelFilter of " + file.path};
    const NormalEdges edges = normalEdges(gbuffer);
    if (edges.hard())
        return {PixelFilter{}, fmt::format("the normal pass has hard edges: {} sharp turns, {} averaged normals",
                                           edges.sharp_turns, edges.short_normals)};
    const bool conclusive = edges.sharp_turns > 0;
    for (const ChannelProfile& p : profileSet(profile_files))
        if (p.name == profile) return {p.pixel_filter, "profile " + profile, conclusive};
    return {PixelFilter{}, "profile " + profile, conclusive};
}

}  // namespace decalcomp
