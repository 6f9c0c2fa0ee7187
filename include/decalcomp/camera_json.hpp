#pragma once
// Camera matrices read from JSON fields (camera sidecars, batch camera lists), refused with the
// field's path when no camera could have them.
#include <glm/glm.hpp>

#include "decalcomp/json_fields.hpp"

namespace decalcomp {

// Invertible and affine: the last row (0, 0, 0, 1), so it moves points without a projection.
glm::dmat4 readWorldToCamera(const JsonField& field);

// Invertible, with the w row of a perspective (0, 0, -1, 0) or orthographic (0, 0, 0, 1)
// projection (any positive scale), near > 0 for perspective and far beyond near; an infinite far
// plane (z row 0 0 -1 -2n) is accepted.
glm::dmat4 readProjection(const JsonField& field);

}  // namespace decalcomp
