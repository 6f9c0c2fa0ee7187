// Decals over time: lifetimes with fades and keyframed placement, evaluated at one frame.
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

#include "decalcomp/decal.hpp"

namespace decalcomp {

namespace {

// M = T * R * S with R a rotation and S symmetric (scale and shear), from the polar
// decomposition of the linear part. A mirrored matrix (det < 0) keeps R proper and S negative.
struct Decomposed {
    glm::dvec3 translate{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
    glm::dmat3 stretch{1.0};
};

glm::dmat3 polarRotation(const glm::dmat3& a) {
    glm::dmat3 x = a;
    for (int i = 0; i < 64; ++i) {
        const glm::dmat3 next = 0.5 * (x + glm::transpose(glm::inverse(x)));
        double change = 0.0;
        for (int c = 0; c < 3; ++c) change = std::max(change, glm::length(next[c] - x[c]));
        x = next;
        if (change < 1e-15) break;
    }
    return x;
}

Decomposed decompose(const glm::dmat4& m) {
    Decomposed d;
    d.translate = glm::dvec3(m[3]);
    glm::dmat3 linear(m);
    const double sign = glm::determinant(linear) < 0.0 ? -1.0 : 1.0;
    const glm::dmat3 rotation = polarRotation(sign * linear);
    glm::dmat3 stretch = glm::transpose(rotation) * linear;
    d.stretch = 0.5 * (stretch + glm::transpose(stretch));
    d.rotation = glm::normalize(glm::quat_cast(rotation));
    return d;
}

glm::dmat4 compose(const Decomposed& d) {
    glm::dmat4 m(glm::mat3_cast(d.rotation) * d.stretch);
    m[3] = glm::dvec4(d.translate, 1.0);
    return m;
}

glm::dmat4 interpolate(const DecalKeyframe& a, const DecalKeyframe& b, double t) {
    const Decomposed da = decompose(a.world_matrix), db = decompose(b.world_matrix);
    Decomposed d;
    d.translate = glm::mix(da.translate, db.translate, t);
    d.rotation = glm::slerp(da.rotation, db.rotation, t);  // shortest arc
    for (int c = 0; c < 3; ++c) d.stretch[c] = glm::mix(da.stretch[c], db.stretch[c], t);
    return compose(d);
}

glm::dmat4 placementAt(const Decal& decal, double frame) {
    const std::vector<DecalKeyframe>& keys = decal.keyframes;
    if (keys.empty()) return decal.world_matrix;
    if (frame <= keys.front().frame) return keys.front().world_matrix;
    if (frame >= keys.back().frame) return keys.back().world_matrix;
    // First key after `frame`; the one before it is at or before `frame`.
    const auto next = std::upper_bound(keys.begin(), keys.end(), frame,
                                       [](double f, const DecalKeyframe& k) { return f < k.frame; });
    const DecalKeyframe& b = *next;
    const DecalKeyframe& a = *(next - 1);
    if (frame == a.frame || decal.keyframe_interpolation == KeyframeInterpolation::Step) return a.world_matrix;
    return interpolate(a, b, (frame - a.frame) / (b.frame - a.frame));
}

// 1 inside the lifetime away from its ends; fade_in = n makes the first n frames 1/(n+1), 2/(n+1),
// ... so the first frame of the lifetime is already visible and frame first + n is fully opaque.
double fadeAt(const Decal& decal, double frame) {
    double factor = 1.0;
    if (decal.first_frame && decal.fade_in_frames > 0.0)
        factor = std::min(factor, (frame - *decal.first_frame + 1.0) / (decal.fade_in_frames + 1.0));
    if (decal.last_frame && decal.fade_out_frames > 0.0)
        factor = std::min(factor, (*decal.last_frame - frame + 1.0) / (decal.fade_out_frames + 1.0));
    return std::clamp(factor, 0.0, 1.0);
}

}  // namespace

std::optional<Decal> decalAtFrame(const Decal& decal, double frame) {
    if (decal.first_frame && frame < *decal.first_frame) return std::nullopt;
    if (decal.last_frame && frame > *decal.last_frame) return std::nullopt;
    Decal out = decal;
    out.world_matrix = placementAt(decal, frame);
    out.opacity = float(double(decal.opacity) * fadeAt(decal, frame));
    return out;
}

std::vector<Decal> decalsAtFrame(const std::vector<Decal>& decals, double frame) {
    std::vector<Decal> out;
    out.reserve(decals.size());
    for (const Decal& d : decals)
        if (auto at = decalAtFrame(d, frame)) out.push_back(std::move(*at));
    return out;
}

DecalScene sceneAtFrame(const DecalScene& scene, double frame) {
    DecalScene out;
    out.textures = scene.textures;
    out.masks = scene.masks;
    out.meshes = scene.meshes;
    out.decals = decalsAtFrame(scene.decals, frame);
    return out;
}

bool hasTextureSpaceDecals(const DecalScene& scene) {
    return std::any_of(scene.decals.begin(), scene.decals.end(),
                       [](const Decal& d) { return d.space == DecalSpace::ObjectRest; });
}

bool isAnimated(const DecalScene& scene) {
    return std::any_of(scene.decals.begin(), scene.decals.end(), [](const Decal& d) { return d.isAnimated(); });
}

}  // namespace decalcomp
