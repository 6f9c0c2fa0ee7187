#include "decalcomp/reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace decalcomp::reference {

namespace {

constexpr double kBackgroundDepth = 1e10;
constexpr double kMinViewDepth = 1e-6;

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Pixel centre in NDC, over the display window.
glm::dvec2 pixelNdc(const GBuffer& f, int x, int y) {
    return {2.0 * (x + f.origin_x + 0.5) / f.display_width - 1.0, 1.0 - 2.0 * (y + f.origin_y + 0.5) / f.display_height};
}

// Camera-space point on the pixel's ray at NDC depth z.
glm::dvec3 unproject(const glm::dmat4& inverse_projection, glm::dvec2 ndc, double z) {
    const glm::dvec4 c = inverse_projection * glm::dvec4(ndc, z, 1.0);
    return glm::dvec3(c) / c.w;
}

std::optional<glm::dvec3> cameraPoint(const GBuffer& f, const Camera& camera, int x, int y) {
    const std::size_t i = std::size_t(y) * f.width + x;
    const bool perspective = !camera.isOrthographic();
    const glm::dmat4 inverse_projection = glm::inverse(camera.projection);
    const glm::dvec2 ndc = pixelNdc(f, x, y);
    const bool has_depth = f.has(Attribute::Depth);
    const double d = has_depth ? f.planes.at(Attribute::Depth).at(i, 0) : 1.0;
    const bool depth_background = !(d > 0.0) || std::isinf(d) || d >= kBackgroundDepth;
    glm::dvec3 p;
    switch (f.depth_convention) {
        case DepthConvention::Position: {
            if (has_depth && depth_background) return std::nullopt;
            const Plane& pos = f.planes.at(Attribute::Position);
            const glm::dvec3 w(pos.at(i, 0), pos.at(i, 1), pos.at(i, 2));
            if (!finite3(w)) return std::nullopt;
            p = glm::dvec3(camera.world_to_camera * glm::dvec4(w, 1.0));
            break;
        }
        case DepthConvention::Ndc: {
            if (std::isnan(d) || d < 0.0 || d > 1.0 || (f.reversed_z ? d <= 0.0 : d >= 1.0)) return std::nullopt;
            p = unproject(inverse_projection, ndc, f.reversed_z ? 1.0 - 2.0 * d : 2.0 * d - 1.0);
            break;
        }
        case DepthConvention::Planar:
        case DepthConvention::Radial: {
            if (depth_background) return std::nullopt;
            const glm::dvec3 near_point = unproject(inverse_projection, ndc, -1.0);
            const glm::dvec3 far_point = unproject(inverse_projection, ndc, 1.0);
            const glm::dvec3 dir = far_point - near_point;
            if (perspective && f.depth_convention == DepthConvention::Radial) {
                p = glm::normalize(dir) * d;  // the ray leaves the camera origin
            } else {
                // intersect the ray with the plane z = -d
                p = near_point + dir * ((-d - near_point.z) / dir.z);
            }
            break;
        }
    }
    if (perspective && !(-p.z >= kMinViewDepth)) return std::nullopt;
    const double far = camera.farPlane();
    if (std::isfinite(far) && far > 0.0 && -p.z > double(float(far))) return std::nullopt;
    if (!finite3(p)) return std::nullopt;
    return p;
}

}  // namespace

std::optional<glm::dvec3> pixelWorldPoint(const GBuffer& frame, const Camera& camera, int x, int y) {
    auto p = cameraPoint(frame, camera, x, y);
    if (!p) return std::nullopt;
    return glm::dvec3(glm::inverse(camera.world_to_camera) * glm::dvec4(*p, 1.0));
}

std::vector<DepthRange> tileDepthRanges(const GBuffer& frame, const Camera& camera, int tile_size) {
    const int tiles_x = (frame.width + tile_size - 1) / tile_size;
    const int tiles_y = (frame.height + tile_size - 1) / tile_size;
    std::vector<DepthRange> ranges(std::size_t(tiles_x) * tiles_y);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const auto p = cameraPoint(frame, camera, x, y);
            if (!p) continue;
            DepthRange& r = ranges[std::size_t(y / tile_size) * tiles_x + x / tile_size];
            const double depth = -p->z;
            r.min = r.empty ? depth : std::min(r.min, depth);
            r.max = r.empty ? depth : std::max(r.max, depth);
            r.empty = false;
        }
    return ranges;
}

std::vector<std::vector<int>> exactBins(const GBuffer& frame, const Camera& camera, const DecalScene& scene,
                                        int tile_size) {
    const int tiles_x = (frame.width + tile_size - 1) / tile_size;
    const int tiles_y = (frame.height + tile_size - 1) / tile_size;
    std::vector<std::vector<char>> hit(std::size_t(tiles_x) * tiles_y, std::vector<char>(scene.decals.size(), 0));
    std::vector<glm::dmat4> world_to_local;
    for (const Decal& d : scene.decals) world_to_local.push_back(glm::inverse(d.world_matrix));
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const auto p = pixelWorldPoint(frame, camera, x, y);
            if (!p) continue;
            auto& tile = hit[std::size_t(y / tile_size) * tiles_x + x / tile_size];
            for (std::size_t k = 0; k < scene.decals.size(); ++k) {
                const glm::dvec3 l(world_to_local[k] * glm::dvec4(*p, 1.0));
                if (std::abs(l.x) <= 0.5 && std::abs(l.y) <= 0.5 && std::abs(l.z) <= 0.5) tile[k] = 1;
            }
        }
    std::vector<std::vector<int>> bins(hit.size());
    for (std::size_t t = 0; t < hit.size(); ++t)
        for (std::size_t k = 0; k < scene.decals.size(); ++k)
            if (hit[t][k]) bins[t].push_back(int(k));
    return bins;
}

glm::dvec4 sampleTexture(const Texture2D& texture, double s, double t, TextureFilter filter) {
    auto texel = [&](long i, long j) {
        i = std::clamp<long>(i, 0, texture.width - 1);
        j = std::clamp<long>(j, 0, texture.height - 1);
        return glm::dvec4(texture.texels[std::size_t(j) * texture.width + std::size_t(i)]);
    };
    const double x = std::clamp(s * texture.width, -1.0, double(texture.width) + 1.0);
    const double y = std::clamp(t * texture.height, -1.0, double(texture.height) + 1.0);
    if (filter == TextureFilter::Nearest) return texel(long(std::floor(x)), long(std::floor(y)));
    // bilinear between the four nearest texel centres, (i + 0.5) / width
    const double fx = x - 0.5, fy = y - 0.5;
    const long i = long(std::floor(fx)), j = long(std::floor(fy));
    const double ax = fx - i, ay = fy - j;
    return (texel(i, j) * (1 - ax) + texel(i + 1, j) * ax) * (1 - ay) +
           (texel(i, j + 1) * (1 - ax) + texel(i + 1, j + 1) * ax) * ay;
}

ShadeResult shade(const GBuffer& frame, const Camera& camera, const DecalScene& scene, double margin) {
    ShadeResult result;
    result.albedo = frame.planes.at(Attribute::Albedo);
    result.ambiguous.assign(frame.pixelCount(), 0);
    std::vector<glm::dmat4> world_to_local;
    std::vector<double> scale;  // how far rounding can move a local coordinate, per unit of |P|
    for (const Decal& d : scene.decals) {
        world_to_local.push_back(glm::inverse(d.world_matrix));
        double row_norm = 0;
        for (int r = 0; r < 3; ++r)
            row_norm = std::max(row_norm, std::abs(world_to_local.back()[0][r]) + std::abs(world_to_local.back()[1][r]) +
                                              std::abs(world_to_local.back()[2][r]));
        scale.push_back(row_norm);
    }
    const glm::dvec3 camera_position(glm::inverse(camera.world_to_camera)[3]);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const auto p = pixelWorldPoint(frame, camera, x, y);
            if (!p) continue;
            const std::size_t i = std::size_t(y) * frame.width + x;
            glm::dvec3 albedo(result.albedo.at(i, 0), result.albedo.at(i, 1), result.albedo.at(i, 2));
            for (std::size_t k = 0; k < scene.decals.size(); ++k) {
                const Decal& decal = scene.decals[k];
                const glm::dvec3 l(world_to_local[k] * glm::dvec4(*p, 1.0));
                // the kernels work in camera space: their error grows with the distance to the camera
                const double slack = margin * scale[k] * (1.0 + glm::length(*p - camera_position));
                const double extent = std::max({std::abs(l.x), std::abs(l.y), std::abs(l.z)});
                if (std::abs(extent - 0.5) <= slack) result.ambiguous[i] = 1;
                if (extent > 0.5 || decal.albedo_texture < 0) continue;
                const Texture2D& texture = scene.textures[std::size_t(decal.albedo_texture)];
                const double s = l.x + 0.5, t = 0.5 - l.y;
                if (decal.filter == TextureFilter::Nearest) {
                    const double sx = s * texture.width, ty = t * texture.height;
                    if (std::abs(sx - std::round(sx)) <= slack * texture.width ||
                        std::abs(ty - std::round(ty)) <= slack * texture.height)
                        result.ambiguous[i] = 1;
                }
                const glm::dvec4 texel = sampleTexture(texture, s, t, decal.filter);
                double weight = decal.opacity;
                if (decal.mask >= 0) weight *= frame.mask_weights[std::size_t(decal.mask)].at(i, 0);
                const double f = std::clamp(texel.a * weight, 0.0, 1.0);
                // straight colour is texel.rgb / alpha; blending by f = alpha * weight
                albedo = albedo * (1.0 - f) + glm::dvec3(texel) * weight;
            }
            for (int c = 0; c < 3; ++c) result.albedo.at(i, c) = float(albedo[c]);
        }
    return result;
}

}  // namespace decalcomp::reference
