#pragma once
// Light passes for synthetic G-buffers, as Blender writes them (divided by the colour): a sun and a
// constant sky, no shadows. The generator's beauty is their sum, so a beauty update is exact.
#include "decalcomp/gbuffer.hpp"

namespace decalcomp::synth {

struct LightPasses {
    Plane direct;    // RGB: sun * max(0, n . l) per unit albedo; 0 on background
    Plane indirect;  // RGB: the sky's constant per unit albedo; 0 on background
    Plane beauty;    // RGBA: albedo * (indirect + direct), alpha 1; transparent black on background
};
// Needs the frame's albedo and (world-space, signed) normal planes.
LightPasses lightPasses(const GBuffer& frame);

}  // namespace decalcomp::synth
