#pragma once
// A pinhole or orthographic camera in decalcomp's conventions (docs/conventions.md):
// right-handed camera space looking down -Z, OpenGL-style projection to NDC in [-1,1].
#include <glm/glm.hpp>
#include <string>

namespace decalcomp {

struct Camera {
    glm::dmat4 world_to_camera{1.0};
    glm::dmat4 projection{1.0};
    std::string source;  // where it came from, for `decalcomp info` ("camera.json", "EXR header ...")

    bool isOrthographic() const;   // projection's last row is (0,0,0,1)
    double nearPlane() const;      // from the projection's z rows (OpenGL convention)
    double farPlane() const;
};

// Throws Error(Input) naming the file and field when a field is missing, malformed or singular.
Camera loadCameraJson(const std::string& path);
void saveCameraJson(const Camera& camera, int width, int height, const std::string& path);

// Builds an OpenGL projection (for generators and tests).
glm::dmat4 perspectiveProjection(double fov_y_rad, double aspect, double near, double far,
                                 double shift_x = 0.0, double shift_y = 0.0);
glm::dmat4 orthographicProjection(double half_height, double aspect, double near, double far);
glm::dmat4 lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up);

// Row-major nested JSON-style arrays <-> GLM (column-major storage).
glm::dmat4 matrixFromRows(const double rows[4][4]);
// Row r of m (GLM stores columns: m[col][row]).
glm::dvec4 matrixRow(const glm::dmat4& m, int r);

}  // namespace decalcomp
