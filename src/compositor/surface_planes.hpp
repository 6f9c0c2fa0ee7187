#pragma once
// The frame's material as the shading kernel reads and writes it: three float4 planes,
// (albedo, roughness), (world-space signed normal, metallic), (emission, ao), packed straight
// from the G-buffer planes into the device's staging memory and unpacked straight back.
#include <array>

#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

constexpr int kSurfaceGroups = 3;

Attribute targetAttribute(DecalTarget target);

// Which targets a frame's groups hold.
struct SurfaceLayout {
    int attributes = 0;  // bits (1 << DC_TARGET_x) of the targets packed
    std::array<bool, kSurfaceGroups> used{};
};

// The planes of `targets` the frame has (albedo always; the normal also when `with_normals`, for
// fades and footprints).
SurfaceLayout surfaceLayout(const GBuffer& frame, const std::array<bool, kDecalTargets>& targets, bool with_normals);

// A run of pixels [first, last) of the frame, so packing and copying can overlap.
struct PixelRange {
    std::size_t first = 0, last = 0;
};

// The packing's threads on this thread while it lives (CompositeOptions::host_threads; 0 leaves
// OpenMP's setting), as before it afterwards. OpenMP keeps the setting per calling thread, so other
// threads' compositors are unaffected.
class HostThreads {
public:
    explicit HostThreads(int threads);
    ~HostThreads();
    HostThreads(const HostThreads&) = delete;
    HostThreads& operator=(const HostThreads&) = delete;

private:
    int before_ = 0;  // 0: unchanged
};

// Copies floats [first, last) of `in` to `out` (both indexed from 0), spread over the host's cores:
// packing is pure memory traffic.
void parallelCopy(float* out, const float* in, PixelRange range);

// Fills pixels `range` of group `group` (4 floats per pixel at `out`, indexed from pixel 0) from
// the frame's planes; normals are decoded from the frame's space and encoding to world space.
// Unused slots are 0.
void packSurfaceGroup(const GBuffer& frame, const Camera& camera, const SurfaceLayout& layout, int group,
                      PixelRange range, float* out);

// Whether group g holds a plane unpackSurfaceGroup writes back (the albedo, or a target some
// decal changes); groups uploaded only to be read (normals for fades) need no read-back.
bool groupWrittenBack(const SurfaceLayout& layout, const std::array<bool, kDecalTargets>& targets, int group);

// Writes the kernel's results for pixels `range` of group `group` back into the frame's planes, for the targets
// in `targets`. Pixels whose normal came back as it was packed keep their original samples bit for
// bit; changed normals are encoded back into the frame's space and encoding.
void unpackSurfaceGroup(GBuffer& frame, const Camera& camera, const SurfaceLayout& layout, int group,
                        PixelRange range, const float* result, const std::array<bool, kDecalTargets>& targets);

}  // namespace decalcomp
