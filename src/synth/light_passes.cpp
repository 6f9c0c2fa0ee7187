#include <glm/glm.hpp>

#include <algorithm>

#include "decalcomp/synth_light.hpp"

namespace decalcomp::synth {

LightPasses lightPasses(const GBuffer& g) {
    const Plane& albedo = g.planes.at(Attribute::Albedo);
    const Plane& normal = g.planes.at(Attribute::Normal);
    const glm::vec3 sun = glm::normalize(glm::vec3(0.4f, -0.6f, 0.7f));
    const float ambient = 0.25f, direct = 0.9f;
    LightPasses out;
    out.direct = {3, std::vector<float>(g.pixelCount() * 3, 0.0f)};
    out.indirect = {3, std::vector<float>(g.pixelCount() * 3, 0.0f)};
    out.beauty = {4, std::vector<float>(g.pixelCount() * 4, 0.0f)};
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        const glm::vec3 n(normal.at(i, 0), normal.at(i, 1), normal.at(i, 2));
        if (!(glm::dot(n, n) > 0.25f)) continue;  // background
        const float sun_light = direct * std::max(0.0f, glm::dot(n, sun));
        const float light = ambient + sun_light;
        for (int c = 0; c < 3; ++c) {
            out.direct.at(i, c) = sun_light;
            out.indirect.at(i, c) = ambient;
            out.beauty.at(i, c) = albedo.at(i, c) * light;
        }
        out.beauty.at(i, 3) = 1.0f;
    }
    return out;
}

}  // namespace decalcomp::synth
