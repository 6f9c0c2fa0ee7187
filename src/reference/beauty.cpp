// The beauty update in double precision, from the formulas of docs/profiles.md "Beauty" (not from
// the kernel): the test oracle of kernels/beauty.h. No relighting.
#include "decalcomp/reference.hpp"

namespace decalcomp::reference {

namespace {

glm::dvec3 rgb(const Plane& plane, std::size_t pixel) {
    return {plane.at(pixel, 0), plane.at(pixel, 1), plane.at(pixel, 2)};
}

void setRgb(Plane& plane, std::size_t pixel, const glm::dvec3& v) {
    for (int c = 0; c < 3; ++c) plane.at(pixel, c) = float(v[c]);
}

}  // namespace

void updateBeauty(const std::map<Attribute, Plane>& before, const std::map<Attribute, Plane>& after,
                  BeautyPlanes& planes) {
    const Plane& albedo_before = before.at(Attribute::Albedo);
    const Plane& albedo_after = after.at(Attribute::Albedo);
    const bool emission = planes.emission && before.count(Attribute::Emission) && after.count(Attribute::Emission);
    for (std::size_t i = 0; i < planes.beauty.samples.size() / 3; ++i) {
        const glm::dvec3 a0 = rgb(albedo_before, i), a1 = rgb(albedo_after, i);
        glm::dvec3 change(0.0);
        if (emission) change += rgb(after.at(Attribute::Emission), i) - rgb(before.at(Attribute::Emission), i);
        if (a0 != a1) {
            for (std::size_t t = 0; t < planes.light.size(); ++t) {
                const glm::dvec3 light = rgb(planes.light[t], i);
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
