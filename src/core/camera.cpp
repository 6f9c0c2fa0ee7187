#include "decalcomp/camera.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>

#include "decalcomp/error.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp {

Camera loadCameraJson(const std::string& path) {
    const nlohmann::json doc = readJsonFile(path, "camera file");
    const JsonField root(doc, path);
    root.requireObject("a JSON object with world_to_camera and projection");
    Camera camera;
    camera.world_to_camera = root.required("world_to_camera").invertibleMatrix4();
    camera.projection = root.required("projection").invertibleMatrix4();
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
