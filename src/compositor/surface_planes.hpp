#pragma once
// The frame's material as the shading kernel reads and writes it: three float4 planes,
// (albedo, roughness), (world-space signed normal, metallic), (emission, ao).
#include <array>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

constexpr int kSurfaceGroups = 3;

Attribute targetAttribute(DecalTarget target);

struct SurfacePlanes {
    int attributes = 0;  // bits (1 << DC_TARGET_x) of the targets packed
    std::array<std::vector<float>, kSurfaceGroups> groups;  // pixels x 4 floats; empty = not used
    bool groupUsed(int g) const { return !groups[std::size_t(g)].empty(); }
};

// Packs the planes of `targets` the frame has (albedo always; the normal also when `with_normals`,
// for fades and footprints). Normals are decoded from the frame's space and encoding to world space.
SurfacePlanes packSurface(const GBuffer& frame, const Camera& camera, const std::array<bool, kDecalTargets>& targets,
                          bool with_normals);

// Whether group g holds a plane unpackSurface writes back (the albedo, or a target some decal
// changes); groups uploaded only to be read (normals for fades) need no read-back.
bool groupWrittenBack(const SurfacePlanes& uploaded, const std::array<bool, kDecalTargets>& targets, int group);

// Writes the kernel's `results` for `targets` back into the frame's planes. Pixels whose
// decoded normal came back unchanged keep their original samples bit for bit; changed normals are
// encoded back into the frame's space and encoding.
void unpackSurface(GBuffer& frame, const Camera& camera, const SurfacePlanes& uploaded,
                   const std::array<std::vector<float>, kSurfaceGroups>& results,
                   const std::array<bool, kDecalTargets>& targets);

}  // namespace decalcomp
