#pragma once
// The synthetic deforming tube's camera and object mask, shared by the texture-space tests
// (test_texture_space.cpp, test_texture_space_bake.cpp).
#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp::test {

// Looks at the tube (synth::tubeMesh) from +X, slightly from -Y, across its UV seam.
inline Camera tubeCamera(int width, int height) {
    Camera camera;
    camera.world_to_camera = lookAt({5.0, -1.0, 1.6}, {0.6, 0.0, 1.0}, {0, 0, 1});
    camera.projection = perspectiveProjection(0.75, double(width) / height, 0.1, 100.0);
    return camera;
}

// Object 1's pixels as the frame's only mask plane (the scenes' masks[0] = ids {1}).
inline void maskObjectOne(GBuffer& g) {
    Plane mask;
    mask.components = 1;
    mask.samples.assign(g.pixelCount(), 0.0f);
    for (std::size_t i = 0; i < g.pixelCount(); ++i) mask.samples[i] = g.planes.at(Attribute::ObjectId).at(i, 0) == 1.0f;
    g.mask_weights = {mask};
}

}  // namespace decalcomp::test
