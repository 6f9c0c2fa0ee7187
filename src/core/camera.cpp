#include "decalcomp/camera.hpp"

#include "decalcomp/camera_json.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "decalcomp/error.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp {

namespace {

double largestEntry(const glm::dmat4& m) {
    double largest = 0.0;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) largest = std::max(largest, std::abs(m[c][r]));
    return largest;
}

std::string rowText(const glm::dvec4& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z, v.w); }

}  // namespace

glm::dmat4 readWorldToCamera(const JsonField& field) {
    const glm::dmat4 m = field.invertibleMatrix4();
    const glm::dvec4 last = matrixRow(m, 3);
    const double tolerance = 1e-9 * std::max(1.0, largestEntry(m));
    if (std::abs(last.x) > tolerance || std::abs(last.y) > tolerance || std::abs(last.z) > tolerance ||
        std::abs(last.w - 1.0) > tolerance)
        field.fail(fmt::format("last row is {}, not (0, 0, 0, 1): world_to_camera must be affine (rotation, "
                               "translation, scale); a projection belongs in \"projection\"",
                               rowText(last)));
    return m;
}

glm::dmat4 readProjection(const JsonField& field) {
    glm::dmat4 m = field.invertibleMatrix4();
    const glm::dvec4 w = matrixRow(m, 3);
    const double tolerance = 1e-9 * std::max(1.0, largestEntry(m));
    const bool perspective = w.z < 0.0 && std::abs(w.x) <= tolerance && std::abs(w.y) <= tolerance &&
                             std::abs(w.w) <= tolerance;
    const bool orthographic = w.w > 0.0 && std::abs(w.x) <= tolerance && std::abs(w.y) <= tolerance &&
                              std::abs(w.z) <= tolerance;
    if (!perspective && !orthographic)
        field.fail(fmt::format("last row is {}: expected (0, 0, -1, 0) for a perspective or (0, 0, 0, 1) for an "
                               "orthographic projection (OpenGL convention, docs/conventions.md)",
                               rowText(w)));
    m /= perspective ? -w.z : w.w;  // the scale of a homogeneous matrix does not matter
    Camera camera;
    camera.projection = m;
    const double near = camera.nearPlane(), far = camera.farPlane();
    if (perspective && !(near > 0.0))
        field.fail(fmt::format("near plane {:.6g}: a perspective projection needs near > 0", near));
    if (!(far > near))
        field.fail(fmt::format("far plane {:.6g} is not beyond the near plane {:.6g}: check the z row's signs "
                               "(OpenGL: -(f+n)/(f-n), -2fn/(f-n))",
                               far, near));
    return m;
}

Camera loadCameraJson(const std::string& path) {
    const nlohmann::json doc = readJsonFile(path, "camera file");
    const JsonField root(doc, path);
    root.requireObject("a JSON object with world_to_camera and projection");
    Camera camera;
    camera.world_to_camera = readWorldToCamera(root.required("world_to_camera"));
    camera.projection = readProjection(root.required("projection"));
    camera.source = path;
    return camera;
}

void saveCameraJson(const Camera& camera, int width, int height, const std::string& path) {
    nlohmann::json doc;
    doc["resolution"] = {width, height};
    doc["matrix_layout"] = "row-major M[row][col], column vectors";
    doc["world_to_camera"] = matrixRowsJson(camera.world_to_camera);
    doc["projection"] = matrixRowsJson(camera.projection);
    std::ofstream out(path);
    if (!out) throw outputError(fmt::format("{}: cannot write camera file", path));
    out << doc.dump(2) << "\n";
    if (!out) throw outputError(fmt::format("{}: write failed", path));
}

}  // namespace decalcomp
