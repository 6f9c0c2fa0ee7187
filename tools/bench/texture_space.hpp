#pragma once
// decalcomp-bench --texture-space: a texture-space box decal on a ~100k-triangle tube against the
// same box placed in the world, on the tube's rest pose, so both cover the same pixels.
#include <cstdio>

#include "decalcomp/compositor.hpp"

namespace decalcomp::bench {

void benchTextureSpace(Compositor& compositor, int width, int height, int repeat, std::FILE* out);

}  // namespace decalcomp::bench
