#include "compositor/surface_planes.hpp"

#include <cstring>

#include "decalcomp/normal_codec.hpp"
#include "shared_types.h"

namespace decalcomp {

namespace {

// Where a target lives: its group and first float within the pixel's float4.
struct Slot {
    int group, first;
};

Slot slotOf(DecalTarget target) {
    switch (target) {
        case DecalTarget::Albedo: return {0, 0};
        case DecalTarget::Roughness: return {0, 3};
        case DecalTarget::Normal: return {1, 0};
        case DecalTarget::Metallic: return {1, 3};
        case DecalTarget::Emission: return {2, 0};
        case DecalTarget::AmbientOcclusion: return {2, 3};
    }
    return {0, 0};
}

int componentsOf(DecalTarget target) {
    return target == DecalTarget::Albedo || target == DecalTarget::Normal || target == DecalTarget::Emission ? 3 : 1;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

Attribute targetAttribute(DecalTarget target) {
    switch (target) {
        case DecalTarget::Albedo: return Attribute::Albedo;
        case DecalTarget::Normal: return Attribute::Normal;
        case DecalTarget::Roughness: return Attribute::Roughness;
        case DecalTarget::Metallic: return Attribute::Metallic;
        case DecalTarget::AmbientOcclusion: return Attribute::AmbientOcclusion;
        case DecalTarget::Emission: return Attribute::Emission;
    }
    return Attribute::Albedo;
}

SurfacePlanes packSurface(const GBuffer& frame, const Camera& camera, const std::array<bool, kDecalTargets>& targets,
                          bool with_normals) {
    SurfacePlanes out;
    const std::size_t pixels = frame.pixelCount();
    const NormalCodec normals(frame.normal_encoding, camera);
    for (int t = 0; t < kDecalTargets; ++t) {
        const auto target = DecalTarget(t);
        const Attribute attribute = targetAttribute(target);
        const bool wanted = target == DecalTarget::Albedo || targets[std::size_t(t)] ||
                            (target == DecalTarget::Normal && with_normals);
        if (!wanted || !frame.has(attribute)) continue;
        const Plane& plane = frame.planes.at(attribute);
        const Slot slot = slotOf(target);
        std::vector<float>& group = out.groups[std::size_t(slot.group)];
        if (group.empty()) group.assign(pixels * 4, 0.0f);
        const int copy = std::min(componentsOf(target), plane.components);
        for (std::size_t i = 0; i < pixels; ++i) {
            if (target == DecalTarget::Normal) {
                glm::vec3 stored(0.0f);
                for (int c = 0; c < copy; ++c) stored[c] = plane.at(i, c);
                const glm::vec3 n = normals.toWorld(stored);
                for (int c = 0; c < 3; ++c) group[i * 4 + std::size_t(c)] = n[c];
            } else {
                for (int c = 0; c < copy; ++c) group[i * 4 + std::size_t(slot.first + c)] = plane.at(i, c);
            }
        }
        out.attributes |= 1 << t;
    }
    return out;
}

bool groupWrittenBack(const SurfacePlanes& uploaded, const std::array<bool, kDecalTargets>& targets, int group) {
    for (int t = 0; t < kDecalTargets; ++t)
        if (slotOf(DecalTarget(t)).group == group && (uploaded.attributes & (1 << t)) &&
            (DecalTarget(t) == DecalTarget::Albedo || targets[std::size_t(t)]))
            return true;
    return false;
}

void unpackSurface(GBuffer& frame, const Camera& camera, const SurfacePlanes& uploaded,
                   const std::array<std::vector<float>, kSurfaceGroups>& results,
                   const std::array<bool, kDecalTargets>& targets) {
    const std::size_t pixels = frame.pixelCount();
    const NormalCodec normals(frame.normal_encoding, camera);
    for (int t = 0; t < kDecalTargets; ++t) {
        const auto target = DecalTarget(t);
        if (!(uploaded.attributes & (1 << t))) continue;
        if (!targets[std::size_t(t)] && target != DecalTarget::Albedo) continue;
        const Slot slot = slotOf(target);
        const std::vector<float>& result = results[std::size_t(slot.group)];
        const std::vector<float>& before = uploaded.groups[std::size_t(slot.group)];
        Plane& plane = frame.planes.at(targetAttribute(target));
        const int copy = std::min(componentsOf(target), plane.components);
        for (std::size_t i = 0; i < pixels; ++i) {
            const float* r = &result[i * 4];
            if (target == DecalTarget::Normal) {
                const float* b = &before[i * 4];
                if (sameBits(r[0], b[0]) && sameBits(r[1], b[1]) && sameBits(r[2], b[2])) continue;
                const glm::vec3 n = normals.toStored(glm::vec3(r[0], r[1], r[2]));
                for (int c = 0; c < copy; ++c) plane.at(i, c) = n[c];
            } else {
                for (int c = 0; c < copy; ++c) plane.at(i, c) = r[slot.first + c];
            }
        }
    }
}

}  // namespace decalcomp
