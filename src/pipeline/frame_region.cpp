// decalReadRegion: the decals' volumes (their corners; a frustum's apex too, since its occlusion
// map reaches back to the origin) through the camera onto display-window pixels.
#include "decalcomp/frame_region.hpp"

#include <algorithm>
#include <cmath>

namespace decalcomp {

namespace {

// Local-space points whose convex hull holds the decal's volume.
std::vector<glm::dvec3> volumeHull(const Decal& decal) {
    std::vector<glm::dvec3> points;
    if (decal.kind == DecalKind::Frustum) {
        const double t = std::tan(glm::radians(decal.fov_y_deg) * 0.5);
        for (double d : {decal.near, decal.far})
            for (double sx : {-1.0, 1.0})
                for (double sy : {-1.0, 1.0}) points.emplace_back(sx * d * t * decal.aspect, sy * d * t, -d);
        points.emplace_back(0.0, 0.0, 0.0);
        return points;
    }
    for (double x : {-0.5, 0.5})  // box, volume and cube kinds live in the unit cube
        for (double y : {-0.5, 0.5})
            for (double z : {-0.5, 0.5}) points.emplace_back(x, y, z);
    return points;
}

}  // namespace

ExrReadRegion decalReadRegion(const std::vector<Decal>& decals, const Camera& camera, const Imath::Box2i& display) {
    ExrReadRegion region;
    region.everything = false;
    const double width = double(display.max.x - display.min.x + 1);
    const double height = double(display.max.y - display.min.y + 1);
    const glm::dmat4 world_to_clip = camera.projection * camera.world_to_camera;
    for (const Decal& decal : decals) {
        double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
        for (const glm::dvec3& local : volumeHull(decal)) {
            const glm::dvec4 clip = world_to_clip * (decal.world_matrix * glm::dvec4(local, 1.0));
            // At or behind the camera's plane the hull's projection is unbounded.
            if (!(clip.w > 1e-9) || !std::isfinite(clip.x) || !std::isfinite(clip.y)) return ExrReadRegion{};
            // NDC -> display pixels: ndc_x = 2(i+0.5)/W - 1, ndc_y = 1 - 2(j+0.5)/H (docs/conventions.md).
            const double px = (clip.x / clip.w + 1.0) * 0.5 * width - 0.5;
            const double py = (1.0 - clip.y / clip.w) * 0.5 * height - 0.5;
            x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
        }
        // Boxes may reach past the display window (overscan data windows) or miss the data
        // window altogether; ExrPart's chunk marking clips them to each part.
        const auto pixel = [&](double v) { return int(std::clamp(v, -1e8, 1e8)); };
        region.boxes.emplace_back(Imath::V2i(display.min.x + pixel(std::floor(x0) - kFootprintMargin),
                                             display.min.y + pixel(std::floor(y0) - kFootprintMargin)),
                                  Imath::V2i(display.min.x + pixel(std::ceil(x1) + kFootprintMargin),
                                             display.min.y + pixel(std::ceil(y1) + kFootprintMargin)));
    }
    return region;
}

}  // namespace decalcomp
