#include "compositor/kernel_params.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

void storeRowMajor(const glm::dmat4& m, float* out, int rows) {
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < 4; ++c) out[r * 4 + c] = float(m[c][r]);
}

int kindCode(DecalKind k) {
    switch (k) {
        case DecalKind::Box: return DC_KIND_BOX;
        case DecalKind::Volume: return DC_KIND_VOLUME;
        case DecalKind::Frustum: return DC_KIND_FRUSTUM;
        case DecalKind::Cube: return DC_KIND_CUBE;
    }
    return DC_KIND_BOX;
}

int conventionCode(DepthConvention c) {
    switch (c) {
        case DepthConvention::Planar: return DC_DEPTH_PLANAR;
        case DepthConvention::Radial: return DC_DEPTH_RADIAL;
        case DepthConvention::Ndc: return DC_DEPTH_NDC;
        case DepthConvention::Position: return DC_DEPTH_POSITION;
    }
    return DC_DEPTH_PLANAR;
}

int opCode(BlendOp op) {
    switch (op) {
        case BlendOp::Over: return DC_OP_OVER;
        case BlendOp::Multiply: return DC_OP_MULTIPLY;
        case BlendOp::Add: return DC_OP_ADD;
        case BlendOp::Replace: return DC_OP_REPLACE;
    }
    return DC_OP_OVER;
}

int normalBlendCode(NormalBlend b) {
    switch (b) {
        case NormalBlend::Reoriented: return DC_NORMAL_RNM;
        case NormalBlend::Udn: return DC_NORMAL_UDN;
        case NormalBlend::Whiteout: return DC_NORMAL_WHITEOUT;
        case NormalBlend::Replace: return DC_NORMAL_REPLACE;
    }
    return DC_NORMAL_RNM;
}

int textureEntry(int scene_index, const std::vector<int>& texture_entries) {
    return scene_index >= 0 ? texture_entries.at(std::size_t(scene_index)) : -1;
}

// The texture set, per-target factors, ops and constants. Targets the decal cannot change (no
// texture, no constant) get factor 0, so the kernel skips them.
void setMaterialParams(const Decal& decal, const std::vector<int>& texture_entries, cl_types::DcDecal& d) {
    d.texture = textureEntry(decal.albedo_texture, texture_entries);
    d.normal_texture = textureEntry(decal.normal_texture, texture_entries);
    d.orm_texture = textureEntry(decal.orm_texture, texture_entries);
    d.emission_texture = textureEntry(decal.emission_texture, texture_entries);
    d.value_mask = 0;
    for (int t = 0; t < kDecalTargets; ++t) {
        const TargetEffect& e = decal.effects[std::size_t(t)];
        d.factor[t] = decalAffects(decal, DecalTarget(t)) ? e.factor : 0.0f;
        d.op[t] = opCode(e.op);
        if (e.value) d.value_mask |= 1 << t;
    }
    const glm::vec3 albedo = decal.effect(DecalTarget::Albedo).value.value_or(glm::vec3(0.0f));
    const glm::vec3 emission = decal.effect(DecalTarget::Emission).value.value_or(glm::vec3(0.0f));
    for (int i = 0; i < 3; ++i) {
        d.albedo_value[i] = albedo[i];
        d.emission_value[i] = emission[i];
    }
    d.roughness_value = decal.effect(DecalTarget::Roughness).value.value_or(glm::vec3(0.0f)).r;
    d.metallic_value = decal.effect(DecalTarget::Metallic).value.value_or(glm::vec3(0.0f)).r;
    d.ao_value = decal.effect(DecalTarget::AmbientOcclusion).value.value_or(glm::vec3(0.0f)).r;
    d.normal_blend = normalBlendCode(decal.normal_blend);
    d.normal_strength = decal.normal_strength;
}

}  // namespace

int tileCount(int pixels) { return (pixels + DC_TILE_SIZE - 1) / DC_TILE_SIZE; }

cl_types::DcFrame makeFrameParams(const GBuffer& frame, const Camera& camera, int decal_count) {
    cl_types::DcFrame f{};
    storeRowMajor(glm::inverse(camera.projection), f.inv_projection, 4);
    storeRowMajor(camera.projection, f.projection, 4);
    storeRowMajor(camera.world_to_camera, f.world_to_camera, 4);
    f.width = frame.width;
    f.height = frame.height;
    f.origin_x = frame.origin_x;
    f.origin_y = frame.origin_y;
    f.display_width = frame.display_width;
    f.display_height = frame.display_height;
    f.depth_convention = conventionCode(frame.depth_convention);
    f.reversed_z = frame.reversed_z ? 1 : 0;
    const double far = camera.farPlane();
    f.far_plane = (std::isfinite(far) && far > 0.0) ? float(far) : 0.0f;
    f.orthographic = camera.isOrthographic() ? 1 : 0;
    f.tiles_x = tileCount(frame.width);
    f.tiles_y = tileCount(frame.height);
    f.decal_count = decal_count;
    f.has_depth = frame.has(Attribute::Depth) ? 1 : 0;
    f.has_normal = frame.has(Attribute::Normal) ? 1 : 0;
    const FilterQuadrature quadrature = filterQuadrature(frame.pixel_filter);
    f.filter_taps = int(quadrature.offsets.size());
    f.filter_step = float(quadrature.step);
    f.filter_radius = float(frame.pixel_filter.radius());
    for (std::size_t i = 0; i < quadrature.offsets.size(); ++i) {
        f.filter_offset[i] = float(quadrature.offsets[i]);
        f.filter_weight[i] = float(quadrature.weights[i]);
    }
    f.filter_box = float(equivalentBoxWidth(frame.pixel_filter));
    f.filter_fast = frame.pixel_filter.fast ? 1 : 0;
    // the table takes milliseconds to integrate: a sequence's frames share their filter's
    thread_local std::pair<PixelFilter, std::vector<double>> edge{PixelFilter{}, edgeSpreadTable(PixelFilter{})};
    if (!(edge.first == frame.pixel_filter)) edge = {frame.pixel_filter, edgeSpreadTable(frame.pixel_filter)};
    std::copy(edge.second.begin(), edge.second.end(), f.filter_edge);
    return f;
}

std::vector<cl_types::DcDecal> makeDecalParams(const DecalScene& scene, const Camera& camera,
                                               const std::vector<int>& texture_entries) {
    const glm::dmat4 camera_to_world = glm::inverse(camera.world_to_camera);
    std::vector<cl_types::DcDecal> out;
    out.reserve(scene.decals.size());
    for (const Decal& decal : scene.decals) {
        cl_types::DcDecal d{};
        // A texture-space decal works in its rest mesh's object space (kernels/rest_pose.h), which
        // stands in for camera space in every field below.
        const bool rest = decal.space == DecalSpace::ObjectRest;
        const glm::dmat4 to_camera = rest ? glm::dmat4(1.0) : camera.world_to_camera;
        const glm::dmat4 camera_to_local = glm::inverse(decal.world_matrix) * (rest ? glm::dmat4(1.0) : camera_to_world);
        storeRowMajor(camera_to_local, d.camera_to_local, 3);
        storeRowMajor(to_camera * decal.world_matrix, d.local_to_camera, 3);
        d.rest_binding = -1;  // bindRestDecals() sets texture-space decals' bindings
        d.rest_baked = decal.baked ? 1 : 0;
        for (int r = 0; r < 3; ++r)
            d.local_scale[r] = float(glm::length(glm::dvec3(camera_to_local[0][r], camera_to_local[1][r], camera_to_local[2][r])));
        d.kind = kindCode(decal.kind);
        d.filter = decal.filter == TextureFilter::Nearest ? DC_FILTER_NEAREST
                   : decal.filter == TextureFilter::Linear ? DC_FILTER_LINEAR
                                                           : DC_FILTER_MIP;
        d.opacity = decal.opacity;
        d.mask = decal.mask;
        d.tan_half_fov_y = float(std::tan(glm::radians(decal.fov_y_deg) / 2.0));
        d.aspect = float(decal.aspect);
        d.near_plane = float(decal.near);
        d.far_plane = float(decal.far);
        const glm::dvec3 facing = glm::normalize(glm::dvec3(to_camera * decal.world_matrix[2]));
        for (int i = 0; i < 3; ++i) d.facing_axis[i] = float(facing[i]);
        d.angle_fade[0] = float(glm::radians(decal.angle_fade_deg[0]));
        d.angle_fade[1] = float(glm::radians(decal.angle_fade_deg[1]));
        d.axis_fade = float(decal.axis_fade);
        d.distance_fade[0] = float(decal.distance_fade[0]);
        d.distance_fade[1] = float(decal.distance_fade[1]);
        setMaterialParams(decal, texture_entries, d);
        out.push_back(d);
    }
    return out;
}

PackedTextures packTextures(const std::vector<Texture2D>& textures) {
    PackedTextures packed;
    for (const auto& t : textures) {
        if (t.width <= 0 || t.height <= 0 || t.depth <= 0 ||
            t.texels.size() != std::size_t(t.width) * std::size_t(t.height) * std::size_t(t.depth))
            throw inputError(t.source + ": texture has no texels");
        packed.first_entry.push_back(int(packed.table.size()));
        const std::vector<Texture2D> chain = mipChain(t);
        for (std::size_t level = 0; level < chain.size(); ++level) {
            const Texture2D& l = chain[level];
            if (packed.texels.size() / 4 + l.texels.size() > std::size_t(INT32_MAX))
                throw inputError("decal textures: more than 2^31 texels in total");
            packed.table.push_back({int(packed.texels.size() / 4), l.width, l.height, l.depth,
                                    int(chain.size() - level), 0, 0, 0});
            for (const auto& texel : l.texels) packed.texels.insert(packed.texels.end(), {texel.r, texel.g, texel.b, texel.a});
        }
    }
    return packed;
}

}  // namespace decalcomp
