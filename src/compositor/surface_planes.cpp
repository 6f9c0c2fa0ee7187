#include "compositor/surface_planes.hpp"

#include <omp.h>

#include <algorithm>
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

// Packing and unpacking are pure memory traffic: spread them over the host's cores for frames
// large enough to pay for the threads.
constexpr std::ptrdiff_t kParallelPixels = 1 << 16;

glm::vec3 storedNormal(const Plane& plane, std::size_t pixel, int copy) {
    glm::vec3 stored(0.0f);
    for (int c = 0; c < copy; ++c) stored[c] = plane.at(pixel, c);
    return stored;
}

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

SurfaceLayout surfaceLayout(const GBuffer& frame, const std::array<bool, kDecalTargets>& targets, bool with_normals) {
    SurfaceLayout layout;
    for (int t = 0; t < kDecalTargets; ++t) {
        const auto target = DecalTarget(t);
        const bool wanted = target == DecalTarget::Albedo || targets[std::size_t(t)] ||
                            (target == DecalTarget::Normal && with_normals);
        if (!wanted || !frame.has(targetAttribute(target))) continue;
        layout.attributes |= 1 << t;
        layout.used[std::size_t(slotOf(target).group)] = true;
    }
    return layout;
}

void packSurfaceGroup(const GBuffer& frame, const Camera& camera, const SurfaceLayout& layout, int group,
                      PixelRange range, float* out) {
    const auto first = std::ptrdiff_t(range.first), last = std::ptrdiff_t(range.last);
    const NormalCodec normals(frame.normal_encoding, camera);
    // One pass per plane, each a plain strided copy into its slots; the first pass writes all four
    // floats, so unused slots are 0 without a separate fill.
    bool first_pass = true;
    for (int t = 0; t < kDecalTargets; ++t) {
        const auto target = DecalTarget(t);
        const Slot slot = slotOf(target);
        if (slot.group != group || !(layout.attributes & (1 << t))) continue;
        const Plane& plane = frame.planes.at(targetAttribute(target));
        const int stride = plane.components, copy = std::min(componentsOf(target), plane.components);
        const float* in = plane.samples.data();
        const bool clear = first_pass;
        first_pass = false;
        const bool is_normal = target == DecalTarget::Normal;
#pragma omp parallel for schedule(static) if (last - first >= kParallelPixels)
        for (std::ptrdiff_t i = first; i < last; ++i) {
            float* o = out + i * 4;
            if (clear) o[0] = o[1] = o[2] = o[3] = 0.0f;
            const float* p = in + i * stride;
            if (is_normal) {
                glm::vec3 stored(0.0f);
                for (int c = 0; c < copy; ++c) stored[c] = p[c];
                const glm::vec3 n = normals.toWorld(stored);
                o[0] = n.x, o[1] = n.y, o[2] = n.z;
            } else {
                for (int c = 0; c < copy; ++c) o[slot.first + c] = p[c];
            }
        }
    }
}

bool groupWrittenBack(const SurfaceLayout& layout, const std::array<bool, kDecalTargets>& targets, int group) {
    for (int t = 0; t < kDecalTargets; ++t)
        if (slotOf(DecalTarget(t)).group == group && (layout.attributes & (1 << t)) &&
            (DecalTarget(t) == DecalTarget::Albedo || targets[std::size_t(t)]))
            return true;
    return false;
}

void unpackSurfaceGroup(GBuffer& frame, const Camera& camera, const SurfaceLayout& layout, int group,
                        PixelRange range, const float* result, const std::array<bool, kDecalTargets>& targets) {
    const auto first = std::ptrdiff_t(range.first), last = std::ptrdiff_t(range.last);
    const NormalCodec normals(frame.normal_encoding, camera);
    for (int t = 0; t < kDecalTargets; ++t) {
        const auto target = DecalTarget(t);
        const Slot slot = slotOf(target);
        if (slot.group != group || !(layout.attributes & (1 << t))) continue;
        if (!targets[std::size_t(t)] && target != DecalTarget::Albedo) continue;
        Plane& plane = frame.planes.at(targetAttribute(target));
        const int copy = std::min(componentsOf(target), plane.components);
        if (target == DecalTarget::Normal) {
#pragma omp parallel for schedule(static) if (last - first >= kParallelPixels)
            for (std::ptrdiff_t i = first; i < last; ++i) {
                const float* r = result + i * 4;
                const glm::vec3 before = normals.toWorld(storedNormal(plane, std::size_t(i), copy));
                if (sameBits(r[0], before.x) && sameBits(r[1], before.y) && sameBits(r[2], before.z)) continue;
                const glm::vec3 n = normals.toStored(glm::vec3(r[0], r[1], r[2]));
                for (int c = 0; c < copy; ++c) plane.at(std::size_t(i), c) = n[c];
            }
            continue;
        }
        float* p = plane.samples.data();
        const int stride = plane.components;
        const float* r = result + slot.first;
#pragma omp parallel for schedule(static) if (last - first >= kParallelPixels)
        for (std::ptrdiff_t i = first; i < last; ++i)
            for (int c = 0; c < copy; ++c) p[i * stride + c] = r[i * 4 + c];
    }
}

HostThreads::HostThreads(int threads) {
    if (threads <= 0) return;
    before_ = omp_get_max_threads();
    omp_set_num_threads(threads);
}

HostThreads::~HostThreads() {
    if (before_ > 0) omp_set_num_threads(before_);
}

void parallelCopy(float* out, const float* in, PixelRange range) {
    constexpr std::size_t kBlock = 1 << 16;
    const auto blocks = std::ptrdiff_t((range.last - range.first + kBlock - 1) / kBlock);
#pragma omp parallel for schedule(static) if (blocks > 1)
    for (std::ptrdiff_t b = 0; b < blocks; ++b) {
        const std::size_t first = range.first + std::size_t(b) * kBlock, n = std::min(range.last - first, kBlock);
        std::memcpy(out + first, in + first, n * sizeof(float));
    }
}

}  // namespace decalcomp
