#include "scene/kind_json.hpp"

#include <fmt/format.h>


#include "decalcomp/camera.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp::scene_detail {

namespace {

// [start, end] with lo <= start < end <= hi.
glm::dvec2 range(const JsonField& v, double lo, double hi) {
    const glm::dvec2 r = v.numberPair();
    if (!(r[0] >= lo && r[0] < r[1] && r[1] <= hi)) v.fail(fmt::format("expected {} <= start < end <= {}", lo, hi));
    return r;
}

void parseFade(const JsonField& fade, Decal& out) {
    fade.requireObject("an object with angle_deg, axis or distance");
    fade.checkKeys({"angle_deg", "axis", "distance"});
    if (const auto angle = fade.optional("angle_deg")) out.angle_fade_deg = range(*angle, 0.0, 180.0);
    if (const auto axis = fade.optional("axis")) {
        if (out.kind != DecalKind::Box && out.kind != DecalKind::Volume) axis->fail("only box and volume decals have an axis fade");
        out.axis_fade = axis->number();
        if (!(out.axis_fade > 0.0 && out.axis_fade <= 1.0)) axis->fail("expected a fraction in (0, 1]");
    }
    if (const auto distance = fade.optional("distance")) {
        if (out.kind != DecalKind::Frustum) distance->fail("only frustum decals have a distance fade");
        out.distance_fade = range(*distance, 0.0, 1e30);
    }
}

// "occlusion": true | false | {"resolution": int in [16, 4096], "bias": number in (0, 64]}.
void parseOcclusion(const JsonField& v, Decal& out) {
    if (out.kind != DecalKind::Frustum && out.kind != DecalKind::Cube)
        v.fail("only frustum and cube decals have blast occlusion");
    if (v.value().is_boolean()) {
        out.occlusion.enabled = v.boolean();
        return;
    }
    v.requireObject("true, false or an object with resolution, bias");
    v.checkKeys({"resolution", "bias"});
    out.occlusion.enabled = true;
    if (const auto resolution = v.optional("resolution")) out.occlusion.resolution = int(resolution->integer(16, 4096));
    if (const auto bias = v.optional("bias")) {
        out.occlusion.bias = bias->number();
        if (!(out.occlusion.bias > 0.0 && out.occlusion.bias <= 64.0)) bias->fail("expected texels in (0, 64]");
    }
}

}  // namespace

std::optional<DecalKind> kindFromName(const std::string& name) {
    for (DecalKind k : {DecalKind::Box, DecalKind::Volume, DecalKind::Frustum, DecalKind::Cube})
        if (name == decalKindName(k)) return k;
    return std::nullopt;
}

bool isProjectorLookAt(const JsonField& decal, DecalKind kind) {
    return kind == DecalKind::Frustum && decal.has("origin") && !decal.has("size");
}

glm::dmat4 projectorLookAt(const JsonField& decal) {
    for (const char* key : {"origin", "target", "up"})
        if (!decal.has(key)) decal.fail(fmt::format("a projector placed by look-at needs '{}'", key));
    const glm::dvec3 origin = decal.required("origin").vec3();
    const glm::dvec3 target = decal.required("target").vec3();
    const glm::dvec3 up = decal.required("up").vec3();
    const glm::dvec3 view = target - origin;
    if (!(glm::length(view) > 0.0)) decal.required("target").fail("equals 'origin' (no view direction)");
    if (!(glm::length(glm::cross(up, view)) > 1e-9 * glm::length(up) * glm::length(view)))
        decal.required("up").fail("zero or parallel to the view direction (origin -> target)");
    return glm::inverse(lookAt(origin, target, up));  // local -Z looks from origin to target
}

void parseKindFields(const JsonField& decal, Decal& out) {
    const bool frustum = out.kind == DecalKind::Frustum;
    for (const char* key : {"fov_y_deg", "aspect", "near", "far"})
        if (decal.has(key) && !frustum) decal.required(key).fail("only frustum decals have this field");
    if (frustum) {
        out.fov_y_deg = decal.optionalNumber("fov_y_deg").value_or(out.fov_y_deg);
        out.aspect = decal.optionalNumber("aspect").value_or(out.aspect);
        out.near = decal.optionalNumber("near").value_or(out.near);
        out.far = decal.optionalNumber("far").value_or(out.far);
        auto failAt = [&](const char* key, const char* what) {
            throw jsonFieldError(decal.file(), jsonKeyPath(decal.path(), key), what);
        };
        if (!(out.fov_y_deg > 0.0 && out.fov_y_deg < 180.0)) failAt("fov_y_deg", "expected degrees in (0, 180)");
        if (!(out.aspect > 0.0)) failAt("aspect", "expected a positive width / height");
        if (!(out.near > 0.0)) failAt("near", "expected a positive distance");
        if (!(out.far > out.near)) failAt("far", "expected a distance beyond 'near'");
    }
    if (const auto fade = decal.optional("fade")) parseFade(*fade, out);
    if (const auto occlusion = decal.optional("occlusion")) parseOcclusion(*occlusion, out);
}

TextureLayout layoutForKind(DecalKind kind, TextureLayout given, const std::string& path, const std::string& file) {
    switch (kind) {
        case DecalKind::Volume:
            if (given == TextureLayout::Image || given == TextureLayout::VolumeStrip) return TextureLayout::VolumeStrip;
            throw jsonFieldError(file, path, "a volume decal needs a volume texture (a vertical strip of square slices)");
        case DecalKind::Cube:
            if (given == TextureLayout::Image || given == TextureLayout::CubeStrip) return TextureLayout::CubeStrip;
            if (given == TextureLayout::CubeFaces) return given;
            throw jsonFieldError(file, path, "a cube decal needs a cube texture (a strip of six faces or 'cube_faces')");
        case DecalKind::Box:
        case DecalKind::Frustum:
            if (given == TextureLayout::Image) return given;
            throw jsonFieldError(file, path, fmt::format("a {} decal needs a 2D image ('albedo')", decalKindName(kind)));
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
