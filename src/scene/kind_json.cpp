#include "scene/kind_json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>

#include "decalcomp/camera.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp::scene_detail {

namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& what) {
    throw inputError(fmt::format("{}: {}: {}", file, path, what));
}

double number(const json& v, const std::string& file, const std::string& path) {
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(file, path, "expected a finite number");
    return v.get<double>();
}

glm::dvec3 vec3(const json& v, const std::string& file, const std::string& path) {
    if (!v.is_array() || v.size() != 3) fail(file, path, "expected 3 numbers");
    return {number(v[0], file, path + "[0]"), number(v[1], file, path + "[1]"), number(v[2], file, path + "[2]")};
}

// [start, end] with lo <= start < end <= hi.
glm::dvec2 range(const json& v, double lo, double hi, const std::string& file, const std::string& path) {
    if (!v.is_array() || v.size() != 2) fail(file, path, "expected two numbers [start, end]");
    const glm::dvec2 r(number(v[0], file, path + "[0]"), number(v[1], file, path + "[1]"));
    if (!(r[0] >= lo && r[0] < r[1] && r[1] <= hi))
        fail(file, path, fmt::format("expected {} <= start < end <= {}", lo, hi));
    return r;
}

void parseFade(const json& fade, const std::string& path, const std::string& file, Decal& out) {
    if (!fade.is_object()) fail(file, path, "expected an object with angle_deg, axis or distance");
    for (const auto& [key, value] : fade.items()) {
        const std::string at = path + "." + key;
        if (key == "angle_deg") {
            out.angle_fade_deg = range(value, 0.0, 180.0, file, at);
        } else if (key == "axis") {
            if (out.kind != DecalKind::Box && out.kind != DecalKind::Volume) fail(file, at, "only box and volume decals have an axis fade");
            out.axis_fade = number(value, file, at);
            if (!(out.axis_fade > 0.0 && out.axis_fade <= 1.0)) fail(file, at, "expected a fraction in (0, 1]");
        } else if (key == "distance") {
            if (out.kind != DecalKind::Frustum) fail(file, at, "only frustum decals have a distance fade");
            out.distance_fade = range(value, 0.0, 1e30, file, at);
        } else if (key.empty() || key[0] != '_') {
            fail(file, at, "unknown fade (supported: angle_deg, axis, distance)");
        }
    }
}

// "occlusion": true | false | {"resolution": int in [16, 4096], "bias": number in (0, 64]}.
void parseOcclusion(const json& v, const std::string& path, const std::string& file, Decal& out) {
    if (out.kind != DecalKind::Frustum && out.kind != DecalKind::Cube)
        fail(file, path, "only frustum and cube decals have blast occlusion");
    if (v.is_boolean()) {
        out.occlusion.enabled = v.get<bool>();
        return;
    }
    if (!v.is_object()) fail(file, path, "expected true, false or an object with resolution, bias");
    out.occlusion.enabled = true;
    for (const auto& [key, value] : v.items()) {
        const std::string at = path + "." + key;
        if (key == "resolution") {
            if (!value.is_number_integer() || value.get<std::int64_t>() < 16 || value.get<std::int64_t>() > 4096)
                fail(file, at, "expected an integer in [16, 4096]");
            out.occlusion.resolution = value.get<int>();
        } else if (key == "bias") {
            const double bias = number(value, file, at);
            if (!(bias > 0.0 && bias <= 64.0)) fail(file, at, "expected texels in (0, 64]");
            out.occlusion.bias = bias;
        } else if (key.empty() || key[0] != '_') {
            fail(file, at, "unknown key (supported: resolution, bias)");
        }
    }
}

}  // namespace

std::optional<DecalKind> kindFromName(const std::string& name) {
    for (DecalKind k : {DecalKind::Box, DecalKind::Volume, DecalKind::Frustum, DecalKind::Cube})
        if (name == decalKindName(k)) return k;
    return std::nullopt;
}

bool isProjectorLookAt(const json& decal, DecalKind kind) {
    return kind == DecalKind::Frustum && decal.contains("origin") && !decal.contains("size");
}

glm::dmat4 projectorLookAt(const json& decal, const std::string& path, const std::string& file) {
    for (const char* key : {"origin", "target", "up"})
        if (!decal.contains(key)) fail(file, path, fmt::format("a projector placed by look-at needs '{}'", key));
    const glm::dvec3 origin = vec3(decal.at("origin"), file, path + ".origin");
    const glm::dvec3 target = vec3(decal.at("target"), file, path + ".target");
    const glm::dvec3 up = vec3(decal.at("up"), file, path + ".up");
    const glm::dvec3 view = target - origin;
    if (!(glm::length(view) > 0.0)) fail(file, path + ".target", "equals 'origin' (no view direction)");
    if (!(glm::length(glm::cross(up, view)) > 1e-9 * glm::length(up) * glm::length(view)))
        fail(file, path + ".up", "zero or parallel to the view direction (origin -> target)");
    return glm::inverse(lookAt(origin, target, up));  // local -Z looks from origin to target
}

void parseKindFields(const json& decal, const std::string& path, const std::string& file, Decal& out) {
    const bool frustum = out.kind == DecalKind::Frustum;
    for (const char* key : {"fov_y_deg", "aspect", "near", "far"})
        if (decal.contains(key) && !frustum) fail(file, path + "." + key, "only frustum decals have this field");
    if (frustum) {
        if (decal.contains("fov_y_deg")) out.fov_y_deg = number(decal.at("fov_y_deg"), file, path + ".fov_y_deg");
        if (decal.contains("aspect")) out.aspect = number(decal.at("aspect"), file, path + ".aspect");
        if (decal.contains("near")) out.near = number(decal.at("near"), file, path + ".near");
        if (decal.contains("far")) out.far = number(decal.at("far"), file, path + ".far");
        if (!(out.fov_y_deg > 0.0 && out.fov_y_deg < 180.0)) fail(file, path + ".fov_y_deg", "expected degrees in (0, 180)");
        if (!(out.aspect > 0.0)) fail(file, path + ".aspect", "expected a positive width / height");
        if (!(out.near > 0.0)) fail(file, path + ".near", "expected a positive distance");
        if (!(out.far > out.near)) fail(file, path + ".far", "expected a distance beyond 'near'");
    }
    if (decal.contains("fade")) parseFade(decal.at("fade"), path + ".fade", file, out);
    if (decal.contains("occlusion")) parseOcclusion(decal.at("occlusion"), path + ".occlusion", file, out);
}

TextureLayout layoutForKind(DecalKind kind, TextureLayout given, const std::string& path, const std::string& file) {
    switch (kind) {
        case DecalKind::Volume:
            if (given == TextureLayout::Image || given == TextureLayout::VolumeStrip) return TextureLayout::VolumeStrip;
            fail(file, path, "a volume decal needs a volume texture (a vertical strip of square slices)");
        case DecalKind::Cube:
            if (given == TextureLayout::Image || given == TextureLayout::CubeStrip) return TextureLayout::CubeStrip;
            if (given == TextureLayout::CubeFaces) return given;
            fail(file, path, "a cube decal needs a cube texture (a strip of six faces or 'cube_faces')");
        case DecalKind::Box:
        case DecalKind::Frustum:
            if (given == TextureLayout::Image) return given;
            fail(file, path, fmt::format("a {} decal needs a 2D image ('albedo')", decalKindName(kind)));
    }
    return given;
}

Texture2D arrangeTexture(Texture2D image, TextureLayout layout) {
    switch (layout) {
        case TextureLayout::VolumeStrip: return volumeFromStrip(std::move(image));
        case TextureLayout::CubeStrip: return cubeFromStrip(image);
        default: return image;
    }
}

}  // namespace decalcomp::scene_detail
