#pragma once
// Decal placement math (no JSON): TRS, rotations and look-at boxes as local->world matrices.
// Callers validate the inputs (non-zero quaternion, origin != target, up not along the view).
#include <glm/glm.hpp>

namespace decalcomp::scene_detail {

// Blender's XYZ Euler order: rotate about X first, then Y, then Z, i.e. R = Rz * Ry * Rx.
glm::dmat3 rotationFromEulerXyzDegrees(const glm::dvec3& degrees);

// Rotation of the unit quaternion (w, x, y, z); q is normalised here.
glm::dmat3 rotationFromQuaternion(double w, double x, double y, double z);

// M = T * R * S: scale in local space, then rotate, then move to `translate`.
glm::dmat4 composeTrs(const glm::dvec3& translate, const glm::dmat3& rotation, const glm::dvec3& scale);

// A box centred at `target` whose local -Z points from `origin` to `target` and whose local +Y is
// `up` made perpendicular to it; `size` = (width, height, depth) along local X, Y, Z.
glm::dmat4 lookAtBox(const glm::dvec3& origin, const glm::dvec3& target, const glm::dvec3& up, const glm::dvec3& size);

}  // namespace decalcomp::scene_detail
