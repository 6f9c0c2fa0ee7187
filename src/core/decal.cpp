#include "decalcomp/decal.hpp"

#include <algorithm>
#include <cmath>

namespace decalcomp {

const char* decalKindName(DecalKind k) {
    switch (k) {
        case DecalKind::Box: return "box";
        case DecalKind::Volume: return "volume";
        case DecalKind::Frustum: return "frustum";
        case DecalKind::Cube: return "cube";
    }
    return "?";
}

const char* textureFilterName(TextureFilter f) {
    switch (f) {
        case TextureFilter::Nearest: return "nearest";
        case TextureFilter::Linear: return "linear";
        case TextureFilter::Mip: return "mip";
    }
    return "?";
}

const char* decalTargetName(DecalTarget t) {
    switch (t) {
        case DecalTarget::Albedo: return "albedo";
        case DecalTarget::Normal: return "normal";
        case DecalTarget::Roughness: return "roughness";
        case DecalTarget::Metallic: return "metallic";
        case DecalTarget::AmbientOcclusion: return "ao";
        case DecalTarget::Emission: return "emission";
    }
    return "?";
}

const char* blendOpName(BlendOp op) {
    switch (op) {
        case BlendOp::Over: return "over";
        case BlendOp::Multiply: return "multiply";
        case BlendOp::Add: return "add";
        case BlendOp::Replace: return "replace";
    }
    return "?";
}

const char* normalBlendName(NormalBlend b) {
    switch (b) {
        case NormalBlend::Reoriented: return "rnm";
        case NormalBlend::Udn: return "udn";
        case NormalBlend::Whiteout: return "whiteout";
        case NormalBlend::Replace: return "replace";
    }
    return "?";
}

std::array<TargetEffect, kDecalTargets> defaultTargetEffects() {
    std::array<TargetEffect, kDecalTargets> effects{};
    effects[std::size_t(DecalTarget::AmbientOcclusion)].op = BlendOp::Multiply;
    effects[std::size_t(DecalTarget::Emission)].op = BlendOp::Add;
    return effects;
}

bool decalAffects(const Decal& decal, DecalTarget target) {
    const TargetEffect& e = decal.effect(target);
    if (!(e.factor > 0.0f)) return false;
    switch (target) {
        case DecalTarget::Albedo: return decal.albedo_texture >= 0 || e.value.has_value();
        case DecalTarget::Normal: return decal.normal_texture >= 0;
        case DecalTarget::Emission: return decal.emission_texture >= 0 || e.value.has_value();
        default: return decal.orm_texture >= 0 || e.value.has_value();
    }
}

std::array<bool, kDecalTargets> sceneTargets(const DecalScene& scene) {
    std::array<bool, kDecalTargets> any{};
    for (const Decal& d : scene.decals)
        for (int t = 0; t < kDecalTargets; ++t) any[std::size_t(t)] = any[std::size_t(t)] || decalAffects(d, DecalTarget(t));
    return any;
}

OcclusionMapSize occlusionMapSize(const Decal& decal) {
    const int r = decal.occlusion.resolution;
    if (decal.kind == DecalKind::Cube) return {r, r, 6};
    // the frustum's far rectangle is aspect : 1; round the shorter side, keep at least one texel
    const double a = decal.aspect;
    const int shorter_w = std::max(1, int(std::lround(r * a))), shorter_h = std::max(1, int(std::lround(r / a)));
    return a >= 1.0 ? OcclusionMapSize{r, shorter_h, 1} : OcclusionMapSize{shorter_w, r, 1};
}

bool isInvertibleDecalMatrix(const glm::dmat4& m) {
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) return false;  // affine only
    const glm::dmat3 linear(m);
    // Relative determinant: |det| against the product of column lengths (1 for orthogonal axes).
    const double scale = glm::length(linear[0]) * glm::length(linear[1]) * glm::length(linear[2]);
    const double det = glm::determinant(linear);
    return std::isfinite(det) && scale > 0.0 && std::abs(det) > 1e-9 * scale && std::abs(det) > 1e-30;
}

}  // namespace decalcomp
