#pragma once
// Antialiased G-buffers with exact filtered truth, for the pixel-filter tests: a frame rendered
// `factor` times finer, then every pass filtered down the way a renderer filters its samples.
#include "decalcomp/gbuffer.hpp"
#include "decalcomp/pixel_filter.hpp"

namespace decalcomp::synth {

// One plane of a fine frame (fine_width x fine_height, factor times the coarse size per axis)
// filtered into coarse pixels: each coarse pixel is the normalised filter-weighted mean of the
// fine samples whose centres lie within the filter's support around its centre.
Plane filterDown(const Plane& fine, int fine_width, int fine_height, int factor, const PixelFilter& filter);

// Every plane and mask of a fine G-buffer filtered down (depth, normals and ids averaged as a
// renderer averages them; background depth takes part like any sample). The result keeps the
// fine frame's conventions and records `filter` as its pixel filter.
GBuffer filterDown(const GBuffer& fine, int factor, const PixelFilter& filter);

}  // namespace decalcomp::synth
