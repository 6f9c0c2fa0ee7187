// Cameras in EXR headers: the standard worldToCamera / worldToNDC attributes (RenderMan
// conventions) converted to and from decalcomp's right-handed, OpenGL-style Camera.
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>

#include "decalcomp/error.hpp"
#include "decalcomp/header_camera.hpp"

namespace decalcomp {

namespace {

// Used when the header has no clipNear/clipFar: worldToNDC carries no depth range, and decalcomp
// only needs the z row for ndc depth, which such files cannot be using anyway.
constexpr double kDefaultNear = 0.1;
constexpr double kDefaultFar = 1e6;

// RenderMan camera space looks down +Z (left-handed); ours looks down -Z.
const glm::dmat4 kFlipZ(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0);

// Imath stores row-vector matrices (p' = p * M) as x[row][col]; the column-vector matrix is the
// transpose, whose GLM storage m[col][row] is therefore element for element the same array.
template <typename ImathMatrix>
glm::dmat4 columnVectorMatrix(const ImathMatrix& m) {
    glm::dmat4 out;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out[i][j] = double(m.x[i][j]);
    return out;
}

Imath::M44f rowVectorMatrix(const glm::dmat4& m) {
    Imath::M44f out;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out.x[i][j] = float(m[i][j]);
    return out;
}

void setRow(glm::dmat4& m, int r, const glm::dvec4& v) {
    for (int c = 0; c < 4; ++c) m[c][r] = v[c];
}

bool allFinite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

std::optional<glm::dmat4> findMatrix(const Imf::Header& header, const char* name, const std::string& file) {
    const auto found = header.find(name);
    if (found == header.end()) return std::nullopt;
    const Imf::Attribute* attribute = &found.attribute();
    glm::dmat4 m;
    if (auto* f = dynamic_cast<const Imf::M44fAttribute*>(attribute))
        m = columnVectorMatrix(f->value());
    else if (auto* d = dynamic_cast<const Imf::M44dAttribute*>(attribute))
        m = columnVectorMatrix(d->value());
    else
        throw inputError(fmt::format("{}: {}: expected an m44f or m44d attribute, got {}", file, name,
                                     attribute->typeName()));
    if (!allFinite(m)) throw inputError(fmt::format("{}: {}: matrix has non-finite entries", file, name));
    return m;
}

std::optional<double> findScalar(const Imf::Header& header, const char* name, const std::string& file) {
    const auto found = header.find(name);
    if (found == header.end()) return std::nullopt;
    const Imf::Attribute* attribute = &found.attribute();
    if (auto* f = dynamic_cast<const Imf::FloatAttribute*>(attribute)) return double(f->value());
    if (auto* d = dynamic_cast<const Imf::DoubleAttribute*>(attribute)) return d->value();
    throw inputError(fmt::format("{}: {}: expected a float or double attribute, got {}", file, name,
                                 attribute->typeName()));
}

void requireInvertible(const glm::dmat4& m, const char* name, const std::string& file) {
    const double det = glm::determinant(m);
    double scale = 0.0;  // relative test, so tiny but well-conditioned scales are not refused
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) scale = std::max(scale, std::abs(m[c][r]));
    if (!std::isfinite(det) || std::abs(det) <= 1e-12 * std::pow(std::max(scale, 1e-300), 4.0))
        throw inputError(fmt::format("{}: {}: matrix is singular", file, name));
}

// World -> RenderMan clip (x_rm*w, y_rm*w, ., w) turned into world -> OpenGL clip for rows x, y, w:
// ndc_x = 2 x_rm - 1 and ndc_y = 1 - 2 y_rm (RenderMan's y runs top to bottom).
glm::dmat4 openGlClipRows(const glm::dmat4& world_to_rm_clip) {
    const glm::dvec4 x = matrixRow(world_to_rm_clip, 0), y = matrixRow(world_to_rm_clip, 1),
                     w = matrixRow(world_to_rm_clip, 3);
    glm::dmat4 n(0.0);
    setRow(n, 0, 2.0 * x - w);
    setRow(n, 1, w - 2.0 * y);
    setRow(n, 3, w);
    return n;
}

struct ClipRange {
    double near_plane, far_plane;
};

ClipRange clipRange(const Imf::Header& header, const std::string& file, bool perspective) {
    const double n = findScalar(header, "clipNear", file).value_or(kDefaultNear);
    const double f = findScalar(header, "clipFar", file).value_or(kDefaultFar);
    // A perspective camera may have an infinite far plane (clipFar = inf).
    const bool far_ok = std::isfinite(f) || (perspective && f == std::numeric_limits<double>::infinity());
    if (!std::isfinite(n) || !far_ok || f <= n || (perspective && n <= 0.0))
        throw inputError(fmt::format("{}: clipNear/clipFar: invalid range [{}, {}]: far must be beyond near (and "
                                     "near > 0 for a perspective camera)",
                                     file, n, f));
    return {n, f};
}

// Normalises the projection's w row to exactly (0,0,-1,0) or (0,0,0,1) and adds the z row, or
// refuses a w row that no pinhole/orthographic camera with this worldToCamera would produce.
void finishProjection(glm::dmat4& p, const Imf::Header& header, const std::string& file, double tolerance) {
    const glm::dvec4 w = matrixRow(p, 3);
    const bool perspective = std::abs(w.z) > std::abs(w.w);
    const double scale = perspective ? -w.z : w.w;
    if (!(scale > 0.0) || !std::isfinite(scale))
        throw inputError(fmt::format("{}: worldToNDC: matrix is singular or looks away from the camera", file));
    p /= scale;
    const glm::dvec4 wn = matrixRow(p, 3);
    const double off_a = std::abs(wn.x), off_b = std::abs(wn.y), off_c = perspective ? std::abs(wn.w) : std::abs(wn.z);
    if (off_a > tolerance || off_b > tolerance || off_c > tolerance)
        throw inputError(fmt::format("{}: worldToNDC: inconsistent with worldToCamera (w row ({:.6g}, {:.6g}, "
                                     "{:.6g}, {:.6g}) in camera space)",
                                     file, wn.x, wn.y, wn.z, wn.w));
    const ClipRange range = clipRange(header, file, perspective);
    const double n = range.near_plane, f = range.far_plane;
    if (perspective) {
        setRow(p, 3, {0.0, 0.0, -1.0, 0.0});
        if (std::isinf(f)) setRow(p, 2, {0.0, 0.0, -1.0, -2.0 * n});  // the limit as far -> infinity
        else setRow(p, 2, {0.0, 0.0, -(f + n) / (f - n), -2.0 * f * n / (f - n)});
    } else {
        setRow(p, 3, {0.0, 0.0, 0.0, 1.0});
        setRow(p, 2, {0.0, 0.0, -2.0 / (f - n), -(f + n) / (f - n)});
    }
}

// Header::insert refuses to change an attribute's type (an m44d worldToNDC, say), and OpenEXR
// 3.1's Header::erase leaks what it drops; so such a header is rebuilt without those attributes.
void dropMistypedAttributes(Imf::Header& header, const std::map<std::string, std::string>& wanted_types) {
    bool mistyped = false;
    for (const auto& [name, type] : wanted_types) {
        const auto it = header.find(name);
        mistyped = mistyped || (it != header.end() && type != it.attribute().typeName());
    }
    if (!mistyped) return;
    Imf::Header rebuilt;
    for (auto it = header.begin(); it != header.end(); ++it)
        if (!wanted_types.count(it.name())) rebuilt.insert(it.name(), it.attribute());
    header = rebuilt;
}

}  // namespace

std::optional<Camera> cameraFromExrHeader(const Imf::Header& header, const std::string& file) {
    const std::optional<glm::dmat4> to_camera = findMatrix(header, "worldToCamera", file);
    const std::optional<glm::dmat4> to_ndc = findMatrix(header, "worldToNDC", file);
    if (!to_camera && !to_ndc) return std::nullopt;
    if (!to_ndc)
        throw inputError(fmt::format("{}: worldToNDC missing (worldToCamera alone does not define the projection)", file));
    if (!to_camera)
        throw inputError(fmt::format("{}: worldToCamera missing (worldToNDC alone does not define the camera)", file));
    requireInvertible(*to_camera, "worldToCamera", file);

    Camera camera;
    camera.world_to_camera = kFlipZ * *to_camera;
    camera.projection = openGlClipRows(*to_ndc) * glm::inverse(camera.world_to_camera);
    // Float attributes: allow their rounding, scaled by how far the camera sits from the origin.
    const double tolerance = 1e-4 * std::max(1.0, glm::length(glm::dvec3(to_camera->operator[](3))));
    finishProjection(camera.projection, header, file, tolerance);
    requireInvertible(camera.projection, "worldToNDC", file);
    camera.source = fmt::format("{} (EXR header worldToCamera/worldToNDC)", file);
    return camera;
}

void writeCameraToExrHeader(const Camera& camera, Imf::Header& header) {
    const glm::dmat4 world_to_clip = camera.projection * camera.world_to_camera;
    const glm::dvec4 x = matrixRow(world_to_clip, 0), y = matrixRow(world_to_clip, 1),
                     z = matrixRow(world_to_clip, 2), w = matrixRow(world_to_clip, 3);
    glm::dmat4 to_ndc(0.0);
    setRow(to_ndc, 0, 0.5 * (x + w));  // x_rm = (ndc_x + 1) / 2
    setRow(to_ndc, 1, 0.5 * (w - y));  // y_rm = (1 - ndc_y) / 2
    setRow(to_ndc, 2, 0.5 * (z + w));  // depth in [0,1] near to far; not read back
    setRow(to_ndc, 3, w);
    dropMistypedAttributes(header, {{"worldToCamera", "m44f"}, {"worldToNDC", "m44f"}, {"clipNear", "float"},
                                    {"clipFar", "float"}});
    header.insert("worldToCamera", Imf::M44fAttribute(rowVectorMatrix(kFlipZ * camera.world_to_camera)));
    header.insert("worldToNDC", Imf::M44fAttribute(rowVectorMatrix(to_ndc)));
    header.insert("clipNear", Imf::FloatAttribute(float(camera.nearPlane())));
    header.insert("clipFar", Imf::FloatAttribute(float(camera.farPlane())));
}

}  // namespace decalcomp
