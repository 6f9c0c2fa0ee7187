#pragma once
// The pixels a frame's decals can reach, known from the camera and the decals' matrices before
// any pixel is read: each decal's volume projected conservatively onto the screen. A frame
// decodes only the chunks these boxes touch (docs/decisions.md, "Decode only what can change").
#include <Imath/ImathBox.h>

#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/pixel_filter.hpp"

namespace decalcomp {

// Extra pixels around each projected volume, against rounding at the edges, and for the pixels
// a pixel filter's taps reach from beyond it.
constexpr int kFootprintMargin = 2 + kMaxFilterReach;

// Absolute EXR pixel boxes (display window `display`) holding every pixel whose centre the
// decals' volumes can cover; everything when a volume reaches behind the camera's plane (its
// projection is unbounded); boxes off screen touch no chunk.
ExrReadRegion decalReadRegion(const std::vector<Decal>& decals, const Camera& camera, const Imath::Box2i& display);

}  // namespace decalcomp
