// The beauty update in double precision, from the formulas of docs/profiles.md "Beauty" (not from
// the kernel): the test oracle of kernels/beauty.h. No relighting.
#include <algorithm>
#include <cmath>

#include "decalcomp/reference.hpp"

namespace decalcomp::reference {

namespace {

glm::dvec3 rgb(const Plane& plane, std::size_t pixel) {
    return {plane.at(pixel, 0), plane.at(pixel, 1), plane.at(pixel, 2)};
}

void setRgb(Plane& plane, std::size_t pixel, const glm::dvec3& v) {
    for (int c = 0; c < 3; ++c) plane.at(pixel, c) = float(v[c]);
}

// The view depth (camera-space -z) of pixel (x, y); nullopt for background.
std::optional<double> viewDepth(const GBuffer& frame, const Camera& camera, int x, int y) {
    const auto p = pixelCameraPoint(frame, camera, x, y);
    if (!p) return std::nullopt;
    return -p->z;
}

// Per channel, the least of light term `term` over the surface pixels `surfaces` around pixel i.
glm::dvec3 leastLight(const Plane& term, std::size_t i, int width, std::uint16_t surfaces) {
    glm::dvec3 least = rgb(term, i);
    for (int k = 0; k < 9; ++k)
        if (surfaces & (1u << k))
            least = glm::min(least, rgb(term, std::size_t(long(i) + long(k / 3 - 1) * width + (k % 3 - 1))));
    return least;
}

}  // namespace

MixedPixels mixedPixels(const GBuffer& frame, const Camera& camera) {
    MixedPixels mixed;
    mixed.width = frame.width;
    mixed.surfaces.assign(frame.pixelCount(), 0);
    const Plane* normal = frame.has(Attribute::Normal) ? &frame.planes.at(Attribute::Normal) : nullptr;
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            const std::size_t i = std::size_t(y) * frame.width + x;
            const auto depth = viewDepth(frame, camera, x, y);
            if (!depth) continue;
            bool is_mixed = false;
            if (normal) {
                glm::dvec3 n = rgb(*normal, i);
                if (frame.normal_encoding.packed) n = 2.0 * n - 1.0;  // a rotation to world keeps the length
                is_mixed = glm::length(n) < 0.995;
            }
            std::uint16_t surfaces = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= frame.width || ny >= frame.height) continue;
                    const auto z = (dx == 0 && dy == 0) ? depth : viewDepth(frame, camera, nx, ny);
                    if (z) surfaces |= std::uint16_t(1u << (3 * (dy + 1) + dx + 1));
                    if (dx != 0 && dy != 0) continue;
                    if (!z || std::abs(*z - *depth) > 0.02 * *depth) is_mixed = true;
                }
            if (is_mixed) mixed.surfaces[i] = surfaces;
        }
    return mixed;
}

void updateBeauty(const std::map<Attribute, Plane>& before, const std::map<Attribute, Plane>& after,
                  BeautyPlanes& planes, const MixedPixels& mixed) {
    const Plane& albedo_before = before.at(Attribute::Albedo);
    const Plane& albedo_after = after.at(Attribute::Albedo);
    const bool emission = planes.emission && before.count(Attribute::Emission) && after.count(Attribute::Emission);
    for (std::size_t i = 0; i < planes.beauty.samples.size() / 3; ++i) {
        const glm::dvec3 a0 = rgb(albedo_before, i), a1 = rgb(albedo_after, i);
        glm::dvec3 change(0.0);
        if (emission) change += rgb(after.at(Attribute::Emission), i) - rgb(before.at(Attribute::Emission), i);
        if (a0 != a1) {
            for (std::size_t t = 0; t < planes.light.size(); ++t) {
                const bool least = planes.divided && !mixed.surfaces.empty() && mixed.surfaces[i] != 0;
                const glm::dvec3 light =
                    least ? leastLight(planes.light[t], i, mixed.width, mixed.surfaces[i]) : rgb(planes.light[t], i);
                glm::dvec3 term_change;
                if (planes.divided) {
                    term_change = light * (a1 - a0);  // light per unit colour
                } else {
                    glm::dvec3 rewritten = light;
                    for (int c = 0; c < 3; ++c)
                        if (a0[c] > 0.0) rewritten[c] = light[c] / a0[c] * a1[c];
                    term_change = rewritten - light;
                    setRgb(planes.light[t], i, rewritten);
                }
                if (int(t) < planes.summed_terms) change += term_change;
            }
        }
        if (change != glm::dvec3(0.0)) setRgb(planes.beauty, i, rgb(planes.beauty, i) + change);
    }
}

}  // namespace decalcomp::reference
