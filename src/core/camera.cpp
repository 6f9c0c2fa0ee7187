#include "decalcomp/camera.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

glm::dmat4 readMatrix(const nlohmann::json& doc, const std::string& field, const std::string& path) {
    if (!doc.contains(field)) throw inputError(fmt::format("{}: {}: missing", path, field));
    const auto& rows = doc[field];
    if (!rows.is_array() || rows.size() != 4)
        throw inputError(fmt::format("{}: {}: expected 4 rows of 4 numbers", path, field));
    double values[4][4];
    for (int r = 0; r < 4; ++r) {
        if (!rows[r].is_array() || rows[r].size() != 4)
            throw inputError(fmt::format("{}: {}[{}]: expected 4 numbers", path, field, r));
        for (int c = 0; c < 4; ++c) {
            if (!rows[r][c].is_number())
                throw inputError(fmt::format("{}: {}[{}][{}]: expected a number", path, field, r, c));
            values[r][c] = rows[r][c].get<double>();
            if (!std::isfinite(values[r][c]))
                throw inputError(fmt::format("{}: {}[{}][{}]: not finite", path, field, r, c));
        }
    }
    return matrixFromRows(values);
}

void requireInvertible(const glm::dmat4& m, const std::string& field, const std::string& path) {
    const double det = glm::determinant(m);
    const glm::dmat4 inv = glm::inverse(m);
    bool finite = std::isfinite(det);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(inv[c][r]);
    if (!finite || std::abs(det) < 1e-12)
        throw inputError(fmt::format("{}: {}: matrix is not invertible", path, field));
}

nlohmann::json rowsOf(const glm::dmat4& m) {
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
    return rows;
}

}  // namespace

Camera loadCameraJson(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw inputError(fmt::format("{}: cannot open camera file", path));
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(in);
    } catch (const nlohmann::json::parse_error& e) {
        throw inputError(fmt::format("{}: not valid JSON (byte {})", path, e.byte));
    }
    if (!doc.is_object()) throw inputError(fmt::format("{}: expected a JSON object", path));
    Camera camera;
    camera.world_to_camera = readMatrix(doc, "world_to_camera", path);
    camera.projection = readMatrix(doc, "projection", path);
    requireInvertible(camera.world_to_camera, "world_to_camera", path);
    requireInvertible(camera.projection, "projection", path);
    camera.source = path;
    return camera;
}

void saveCameraJson(const Camera& camera, int width, int height, const std::string& path) {
    nlohmann::json doc;
    doc["resolution"] = {width, height};
    doc["matrix_layout"] = "row-major M[row][col], column vectors";
    doc["world_to_camera"] = rowsOf(camera.world_to_camera);
    doc["projection"] = rowsOf(camera.projection);
    std::ofstream out(path);
    if (!out) throw outputError(fmt::format("{}: cannot write camera file", path));
    out << doc.dump(2) << "\n";
    if (!out) throw outputError(fmt::format("{}: write failed", path));
}

}  // namespace decalcomp
