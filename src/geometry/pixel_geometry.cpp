// The background rule and pixel -> camera/world point reconstruction (docs/conventions.md).
#include "decalcomp/geometry.hpp"

#include <cmath>

namespace decalcomp {

namespace {

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

bool isBackgroundDepth(DepthConvention convention, bool reversed_z, double d) {
    if (std::isnan(d)) return true;
    if (convention == DepthConvention::Ndc) return d < 0.0 || d > 1.0 || (reversed_z ? d <= 0.0 : d >= 1.0);
    return !(d > 0.0) || std::isinf(d) || d >= kBackgroundDepth;
}

bool isGeometryPixel(const GBuffer& g, std::size_t i) {
    if (g.has(Attribute::Depth))
        return !isBackgroundDepth(g.depth_convention, g.reversed_z, g.planes.at(Attribute::Depth).at(i, 0));
    if (!g.has(Attribute::Position)) return false;
    const Plane& p = g.planes.at(Attribute::Position);
    return finite3(glm::dvec3(p.at(i, 0), p.at(i, 1), p.at(i, 2)));
}

glm::dvec2 displayPixelToNdc(const GBuffer& g, const glm::dvec2& pixel) {
    return {2.0 * pixel.x / g.display_width - 1.0, 1.0 - 2.0 * pixel.y / g.display_height};
}

glm::dvec2 pixelNdc(const GBuffer& g, int x, int y) {
    return displayPixelToNdc(g, {x + g.origin_x + 0.5, y + g.origin_y + 0.5});
}

glm::dvec3 unprojectNdc(const glm::dmat4& inverse_projection, const glm::dvec2& ndc, double ndc_z) {
    const glm::dvec4 c = inverse_projection * glm::dvec4(ndc, ndc_z, 1.0);
    return glm::dvec3(c) / c.w;
}

std::optional<glm::dvec3> pixelCameraPoint(const GBuffer& g, const Camera& camera, int x, int y) {
    const std::size_t i = std::size_t(y) * std::size_t(g.width) + std::size_t(x);
    const bool orthographic = camera.isOrthographic();
    const bool has_depth = g.has(Attribute::Depth);
    const double d = has_depth ? double(g.planes.at(Attribute::Depth).at(i, 0)) : 1.0;
    if (has_depth && isBackgroundDepth(g.depth_convention, g.reversed_z, d)) return std::nullopt;
    glm::dvec3 p;
    if (g.depth_convention == DepthConvention::Position) {
        if (!g.has(Attribute::Position)) return std::nullopt;
        const Plane& position = g.planes.at(Attribute::Position);
        const glm::dvec3 w(position.at(i, 0), position.at(i, 1), position.at(i, 2));
        if (!finite3(w)) return std::nullopt;
        p = glm::dvec3(camera.world_to_camera * glm::dvec4(w, 1.0));
    } else {
        if (!has_depth) return std::nullopt;
        const glm::dmat4 inverse_projection = glm::inverse(camera.projection);
        const glm::dvec2 ndc = pixelNdc(g, x, y);
        if (g.depth_convention == DepthConvention::Ndc) {
            p = unprojectNdc(inverse_projection, ndc, g.reversed_z ? 1.0 - 2.0 * d : 2.0 * d - 1.0);
        } else if (orthographic) {  // planar and radial agree: the ray runs along -Z
            const glm::dvec3 a = unprojectNdc(inverse_projection, ndc, -1.0);
            p = glm::dvec3(a.x, a.y, -d);
        } else {
            const glm::dvec3 q = unprojectNdc(inverse_projection, ndc, 0.0);  // on the ray, in front; finite if far = inf
            p = g.depth_convention == DepthConvention::Radial ? glm::normalize(q) * d : q * (d / -q.z);
        }
    }
    if (!orthographic && !(-p.z >= kMinViewDepth)) return std::nullopt;
    // compared at float precision, as the kernels do
    const double far = camera.farPlane();
    if (std::isfinite(far) && far > 0.0 && -p.z > double(float(far))) return std::nullopt;
    if (!finite3(p)) return std::nullopt;
    return p;
}

std::optional<glm::dvec3> pixelWorldPoint(const GBuffer& g, const Camera& camera, int x, int y) {
    const auto p = pixelCameraPoint(g, camera, x, y);
    if (!p) return std::nullopt;
    return glm::dvec3(glm::inverse(camera.world_to_camera) * glm::dvec4(*p, 1.0));
}

}  // namespace decalcomp
