#pragma once
// The beauty and the albedo lobe's light planes as the shading kernel reads and writes them:
// packed RGB, three floats per pixel as the planes hold them, terms back to back. No unused fourth
// float: the update is memory traffic, and the beauty's own planes upload without a repack.
#include <cstddef>

#include "decalcomp/beauty.hpp"
#include "shared_types.h"

namespace decalcomp {

// Bytes per pixel of the beauty and of each light term on the device.
inline constexpr std::size_t kBeautyPixelBytes = 3 * sizeof(float);

// Whether the device gets the summed terms as one: divided light that is not relit is never
// rewritten, and its summed terms only ever add up, so one term of their sum carries the whole
// update (Combined' = Combined + (DiffDir + DiffInd) (DiffCol' - DiffCol) as the formula reads) in
// half the traffic. Not on filtered frames, whose mixed pixels take the least light per term.
bool foldsLightTerms(const BeautyPlanes& planes, bool filtered);
// The light terms the device holds.
std::size_t deviceLightTerms(const BeautyPlanes& planes, bool fold);

// The DcFrame fields of the beauty update; all off without planes.
void setBeautyParams(cl_types::DcFrame& params, const BeautyPlanes* planes, bool fold);

// Throws Error(Input) when a plane does not cover `pixels` with 3 components.
void checkBeautyPlanes(const BeautyPlanes& planes, std::size_t pixels);

// Fills `beauty` (pixels x RGB) and `light` (device terms x pixels x RGB) from the planes.
void packBeautyPlanes(const BeautyPlanes& planes, bool fold, float* beauty, float* light);
// Writes the kernel's results back: the beauty, and the light terms when the kernel rewrote them.
void unpackBeautyPlanes(BeautyPlanes& planes, const float* beauty, const float* light);

}  // namespace decalcomp
