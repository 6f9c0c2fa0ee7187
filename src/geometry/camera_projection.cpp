// Camera's projection math and the matrix builders (docs/conventions.md "Camera"); loading and
// saving camera files is src/core/camera.cpp.
#include "decalcomp/camera.hpp"

#include <cmath>
#include <limits>

namespace decalcomp {

bool Camera::isOrthographic() const {
    // GLM is column-major: projection[col][row]. Last row = (0,0,0,1) means no perspective divide.
    return projection[0][3] == 0.0 && projection[1][3] == 0.0 && projection[2][3] == 0.0 &&
           projection[3][3] != 0.0;
}

double Camera::nearPlane() const {
    const double a = projection[2][2], b = projection[3][2];
    if (isOrthographic()) return (b + 1.0) / a;  // z_ndc = a z + b; z = -n at ndc -1
    return b / (a - 1.0);
}

double Camera::farPlane() const {
    const double a = projection[2][2], b = projection[3][2];
    if (isOrthographic()) return (b - 1.0) / a;
    // An infinite projection (z row 0 0 -1 -2n) maps only infinity to ndc 1.
    if (std::abs(a + 1.0) <= 1e-12 * std::abs(a)) return std::numeric_limits<double>::infinity();
    return b / (a + 1.0);
}

glm::dvec4 matrixRow(const glm::dmat4& m, int r) { return {m[0][r], m[1][r], m[2][r], m[3][r]}; }

glm::dmat4 matrixFromRows(const double rows[4][4]) {
    glm::dmat4 m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[c][r] = rows[r][c];
    return m;
}

glm::dmat4 perspectiveProjection(double fov_y_rad, double aspect, double near, double far, double shift_x,
                                 double shift_y) {
    const double f = 1.0 / std::tan(fov_y_rad / 2.0);
    glm::dmat4 p(0.0);
    p[0][0] = f / aspect;
    p[1][1] = f;
    p[2][0] = 2.0 * shift_x;  // lens shift in NDC half-units, like Blender's shift x2
    p[2][1] = 2.0 * shift_y;
    p[2][2] = -(far + near) / (far - near);
    p[2][3] = -1.0;
    p[3][2] = -2.0 * far * near / (far - near);
    return p;
}

glm::dmat4 orthographicProjection(double half_height, double aspect, double near, double far) {
    glm::dmat4 p(1.0);
    p[0][0] = 1.0 / (half_height * aspect);
    p[1][1] = 1.0 / half_height;
    p[2][2] = -2.0 / (far - near);
    p[3][2] = -(far + near) / (far - near);
    return p;
}

glm::dmat4 lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up) {
    const glm::dvec3 f = glm::normalize(target - eye);
    const glm::dvec3 s = glm::normalize(glm::cross(f, up));
    const glm::dvec3 u = glm::cross(s, f);
    glm::dmat4 m(1.0);
    for (int i = 0; i < 3; ++i) {
        m[i][0] = s[i];
        m[i][1] = u[i];
        m[i][2] = -f[i];
    }
    m[3][0] = -glm::dot(s, eye);
    m[3][1] = -glm::dot(u, eye);
    m[3][2] = glm::dot(f, eye);
    return m;
}

}  // namespace decalcomp
