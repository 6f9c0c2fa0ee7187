#pragma once
// The albedo lobe's light planes as the shading kernel reads (and, multiplied, rewrites) them, and
// the beauty's changes it writes: packed RGB, three floats per pixel as the planes hold them, terms
// back to back. No unused fourth float: the update is memory traffic, and the light planes upload
// without a repack.
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

// The kernel never reads the beauty: it writes the beauty's change at every pixel of a tile with a
// decal listed on it, and the host adds the changes (kernels/beauty.h). A changed pixel costs the
// device its light terms' reads alone, and the beauty crosses to the device not at all.
// With one folded term (foldsLightTerms), which only its own pixel reads, the changes overwrite the
// term in its buffer (DcFrame::change_in_light): a CPU device then writes cache lines it has just
// read instead of fetching a second buffer's lines to write them.

// Where the kernel wrote changes: the pixels of tiles (DC_TILE_SIZE square, `tiles_x` per row) whose
// list in the binning's `tile_offsets` (tiles + 1) is not empty; unbinned (no offsets), every pixel
// when `decals` > 0.
struct BeautyChangeTiles {
    const cl_int* tile_offsets = nullptr;
    int tiles_x = 0;
    int decals = 0;
};

// Fills `light` (device terms x pixels x RGB) from the planes.
void packLightTerms(const BeautyPlanes& planes, bool fold, float* light);
// Writes the kernel's results back: the beauty plus its changes (a change of 0 leaves the pixel's
// bits as they are), and the light terms when the kernel rewrote them.
void unpackBeautyPlanes(BeautyPlanes& planes, int width, int height, const BeautyChangeTiles& where,
                        const float* changes, const float* light);

}  // namespace decalcomp
