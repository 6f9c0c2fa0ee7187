#pragma once
// The beauty and the albedo lobe's light planes as the shading kernel reads and writes them:
// one float4 per pixel (RGB, unused w) for the beauty and for each light term, terms back to back.
#include <cstddef>

#include "decalcomp/beauty.hpp"
#include "shared_types.h"

namespace decalcomp {

// The DcFrame fields of the beauty update; all off without planes.
void setBeautyParams(cl_types::DcFrame& params, const BeautyPlanes* planes);

// Throws Error(Input) when a plane does not cover `pixels` with 3 components.
void checkBeautyPlanes(const BeautyPlanes& planes, std::size_t pixels);

// Fills `beauty` (pixels float4) and `light` (terms x pixels float4) from the planes.
void packBeautyPlanes(const BeautyPlanes& planes, float* beauty, float* light);
// Writes the kernel's results back: the beauty, and the light terms when the kernel rewrote them.
void unpackBeautyPlanes(BeautyPlanes& planes, const float* beauty, const float* light);

}  // namespace decalcomp
