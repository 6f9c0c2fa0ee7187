#pragma once
// decalcomp-bench --texture-space: a texture-space box decal on a ~100k-triangle tube against the
// same box placed in the world, on the tube's rest pose, so both cover the same pixels.
#include <cstdio>

#include "decalcomp/compositor.hpp"
#include "decalcomp/rest_mesh.hpp"

namespace decalcomp::bench {

// The tube (rest pose, 102,400 triangles) rendered at width x height with its object mask, and a
// world box decal through its front (scene.decals[0]; the scene holds the tube as mesh 0).
struct TubeBench {
    RestMesh tube;
    Camera camera;
    GBuffer frame;
    DecalScene scene;
};
TubeBench tubeBench(int width, int height);

// Medians over `repeat` composites of `frame` after setScene(scene) and one warm-up.
struct Timing {
    double kernel_ms = 0, rest_ms = 0, shading_ms = 0, wall_ms = 0;
    std::size_t changed = 0;  // albedo pixels the decal changed
};
Timing timeFrames(Compositor& compositor, const DecalScene& scene, const GBuffer& frame, const Camera& camera,
                  int repeat);

void benchTextureSpace(Compositor& compositor, int width, int height, int repeat, std::FILE* out);

}  // namespace decalcomp::bench
