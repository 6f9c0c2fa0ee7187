#pragma once
// decalcomp-bench --bake: the texture-space bake kernel alone on the 102,400-triangle tube at 1024²
// and 2048², then one frame with the decal in bake mode, in exact mode and as a world box of the
// same coverage (docs/benchmarks.md "Texture-space bake").
#include <cstdio>

#include "decalcomp/compositor.hpp"

namespace decalcomp::bench {

void benchBake(ComputeDevice& device, Compositor& compositor, int width, int height, int repeat, std::FILE* out);

}  // namespace decalcomp::bench
