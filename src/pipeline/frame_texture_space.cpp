#include "pipeline/frame_texture_space.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "decalcomp/error.hpp"
#include "decalcomp/rest_mesh.hpp"

namespace decalcomp {

namespace {

// How many of a binding's object pixels land on its mesh, reading v as stored and flipped.
struct UvHits {
    std::size_t object = 0, sampled = 0, as_stored = 0, flipped = 0;
};

// Up to ~4096 of the object's pixels, evenly strided: enough to tell the two readings apart.
UvHits countHits(const RestMesh& mesh, int mask, const GBuffer& gbuffer) {
    UvHits hits;
    const Plane& uv = gbuffer.planes.at(Attribute::UV);
    const std::size_t pixels = gbuffer.pixelCount();
    std::vector<std::size_t> object;
    for (std::size_t i = 0; i < pixels; ++i) {
        if (mask >= 0 && !(gbuffer.mask_weights[std::size_t(mask)].at(i, 0) > 0.0f)) continue;
        if (!std::isfinite(uv.at(i, 0)) || !std::isfinite(uv.at(i, 1))) continue;
        object.push_back(i);
    }
    hits.object = object.size();
    const std::size_t stride = std::max<std::size_t>(1, object.size() / 4096);
    for (std::size_t k = 0; k < object.size(); k += stride) {
        ++hits.sampled;
        const glm::vec2 p(uv.at(object[k], 0), uv.at(object[k], 1));
        hits.as_stored += findRestPoint(mesh, p).has_value();
        hits.flipped += findRestPoint(mesh, glm::vec2(p.x, 1.0f - p.y)).has_value();
    }
    return hits;
}

std::string decalNames(const std::vector<const Decal*>& decals) {
    std::vector<std::string> names;
    for (const Decal* d : decals) names.push_back("'" + d->name + "'");
    return fmt::format("{}", fmt::join(names, ", "));
}

}  // namespace

void settleTextureSpace(const DecalScene& scene, const std::vector<Decal>& decals, const ChannelMapping& mapping,
                        std::optional<bool> uv_v_down, const std::string& label, GBuffer& gbuffer,
                        std::vector<std::string>& warnings) {
    std::map<std::pair<int, int>, std::vector<const Decal*>> bindings;  // (mesh, mask) -> its decals
    for (const Decal& d : decals)
        if (d.space == DecalSpace::ObjectRest) bindings[{d.rest_mesh, d.mask}].push_back(&d);
    if (bindings.empty()) return;
    if (!gbuffer.has(Attribute::UV))
        throw inputError(fmt::format("{}: texture-space decal {} needs a UV pass, and the frame has none (profile {}; "
                                     "Blender: <ViewLayer>.UV.U/V); render the UV pass or map it with --channel "
                                     "uv=U,V",
                                     label, decalNames(bindings.begin()->second), mapping.profile));
    std::map<std::pair<int, int>, UvHits> hits;
    UvHits total;
    for (const auto& [key, users] : bindings) {
        const UvHits h = countHits(scene.meshes.at(std::size_t(key.first)), key.second, gbuffer);
        hits[key] = h;
        total.sampled += h.sampled;
        total.as_stored += h.as_stored;
        total.flipped += h.flipped;
    }
    if (uv_v_down) {
        gbuffer.uv_v_down = *uv_v_down;
    } else {
        // v runs bottom-up in OBJ and in every renderer profile. A pass read the right way puts
        // (nearly) every object pixel on its mesh; one that lands clearly more often flipped, and
        // then almost always, was written top-down. Layouts that fill the UV square both ways
        // cannot tell, and stay as stored.
        gbuffer.uv_v_down = 10 * total.flipped >= 9 * total.sampled &&
                            total.flipped > total.as_stored + std::max<std::size_t>(8, total.sampled / 20);
        if (gbuffer.uv_v_down)
            warnings.push_back(fmt::format(
                "{}: UV pass: its v runs top-down against the rest meshes' bottom-up UVs ({} sampled object pixels land "
                "on the mesh flipped, {} as stored), so it is read flipped; --uv-origin bottom reads it as stored",
                label, total.flipped, total.as_stored));
    }
    for (const auto& [key, users] : bindings) {
        const UvHits& h = hits[key];
        const std::size_t landed = gbuffer.uv_v_down ? h.flipped : h.as_stored;
        const std::string& mesh = scene.meshes.at(std::size_t(key.first)).source;
        if (h.object == 0)
            warnings.push_back(fmt::format("{}: texture-space decal {}: no pixel of its object is in this frame (check "
                                           "its pass_index or cryptomatte_object); it changes nothing here",
                                           label, decalNames(users)));
        else if (landed == 0)
            warnings.push_back(fmt::format("{}: texture-space decal {}: none of its object's {} pixels has a UV on {} "
                                           "(is it the mesh that was rendered, with the same UV map? --uv-origin "
                                           "top|bottom sets the v direction); it changes nothing here",
                                           label, decalNames(users), h.object, mesh));
    }
}

}  // namespace decalcomp
