#include "scene/placement.hpp"

#include <cmath>
#include <numbers>

namespace decalcomp::scene_detail {
namespace {

// GLM indexes m[column][row]; these keep the formulas readable in the usual row-major notation.
void setRow(glm::dmat3& m, int row, double a, double b, double c) {
    m[0][row] = a;
    m[1][row] = b;
    m[2][row] = c;
}

}  // namespace

glm::dmat3 rotationFromEulerXyzDegrees(const glm::dvec3& degrees) {
    const glm::dvec3 r = degrees * (std::numbers::pi / 180.0);
    const double cx = std::cos(r.x), sx = std::sin(r.x);
    const double cy = std::cos(r.y), sy = std::sin(r.y);
    const double cz = std::cos(r.z), sz = std::sin(r.z);
    glm::dmat3 rx, ry, rz;
    setRow(rx, 0, 1, 0, 0);
    setRow(rx, 1, 0, cx, -sx);
    setRow(rx, 2, 0, sx, cx);
    setRow(ry, 0, cy, 0, sy);
    setRow(ry, 1, 0, 1, 0);
    setRow(ry, 2, -sy, 0, cy);
    setRow(rz, 0, cz, -sz, 0);
    setRow(rz, 1, sz, cz, 0);
    setRow(rz, 2, 0, 0, 1);
    return rz * ry * rx;
}

glm::dmat3 rotationFromQuaternion(double w, double x, double y, double z) {
    const double n = std::sqrt(w * w + x * x + y * y + z * z);
    w /= n;
    x /= n;
    y /= n;
    z /= n;
    glm::dmat3 m;
    setRow(m, 0, 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y));
    setRow(m, 1, 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x));
    setRow(m, 2, 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y));
    return m;
}

glm::dmat4 composeTrs(const glm::dvec3& translate, const glm::dmat3& rotation, const glm::dvec3& scale) {
    glm::dmat4 m(1.0);
    for (int c = 0; c < 3; ++c) m[c] = glm::dvec4(rotation[c] * scale[c], 0.0);  // R * S: scale columns
    m[3] = glm::dvec4(translate, 1.0);
    return m;
}

glm::dmat4 lookAtBox(const glm::dvec3& origin, const glm::dvec3& target, const glm::dvec3& up, const glm::dvec3& size) {
    // Same frame as a camera at `origin` looking at `target`: -Z forward, +Y up, +X right, so the
    // image reads upright and unmirrored from the origin.
    const glm::dvec3 z = glm::normalize(origin - target);
    const glm::dvec3 x = glm::normalize(glm::cross(up, z));
    const glm::dvec3 y = glm::cross(z, x);
    glm::dmat3 rotation(x, y, z);
    return composeTrs(target, rotation, size);
}

}  // namespace decalcomp::scene_detail
