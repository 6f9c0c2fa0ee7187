// Random decal scenes on top of a rendered frame, for tests and benchmarks.
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <algorithm>
#include <random>

#include "decalcomp/geometry.hpp"
#include "decalcomp/synth.hpp"

namespace decalcomp::synth {

Texture2D proceduralTexture(int kind, int size, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const glm::vec3 colour(u(rng), u(rng), u(rng));
    Texture2D t;
    t.source = "procedural";
    t.width = t.height = size;
    t.texels.resize(std::size_t(size) * size);
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const float x = (i + 0.5f) / size - 0.5f, y = (j + 0.5f) / size - 0.5f;
            const float r = std::sqrt(x * x + y * y);
            float alpha = 1.0f;
            glm::vec3 c = colour;
            switch (kind % 3) {
                case 0: alpha = (r > 0.3f && r < 0.45f) ? 1.0f : 0.0f; break;         // ring
                case 1: c = ((i * 4 / size + j * 4 / size) & 1) ? colour : glm::vec3(1.0f) - colour; break;  // checker
                default: alpha = glm::clamp(1.0f - r / 0.5f, 0.0f, 1.0f); break;      // soft spot
            }
            t.texels[std::size_t(j) * size + i] = glm::vec4(c * alpha, alpha);
        }
    return t;
}

DecalScene scatterDecals(const GBuffer& frame, const Camera& camera, const ScatterOptions& options) {
    std::mt19937 rng(options.seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    DecalScene scene;
    for (int k = 0; k < options.texture_count; ++k)
        scene.textures.push_back(proceduralTexture(k, options.texture_size, options.seed * 977u + k));
    const int last_row = options.last_row < 0 ? frame.height - 1 : std::min(options.last_row, frame.height - 1);
    std::uniform_int_distribution<int> px(0, frame.width - 1), py(std::max(0, options.first_row), last_row);
    for (int n = 0; n < options.count; ++n) {
        std::optional<glm::dvec3> centre;
        for (int attempt = 0; attempt < 32 && !centre; ++attempt)
            centre = pixelWorldPoint(frame, camera, px(rng), py(rng));
        if (!centre) centre = glm::dvec3(0.0);
        const glm::dvec3 axis = glm::normalize(glm::dvec3(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5) + 1e-9);
        const double size = options.min_size + (options.max_size - options.min_size) * u01(rng);
        glm::dmat4 m = glm::translate(glm::dmat4(1.0), *centre);
        m = glm::rotate(m, u01(rng) * 6.283185307179586, axis);
        m = glm::scale(m, glm::dvec3(size, size * (0.5 + u01(rng)), size * (0.5 + u01(rng))));
        Decal d;
        d.name = "scatter" + std::to_string(n);
        d.world_matrix = m;
        d.albedo_texture = int(rng() % scene.textures.size());
        d.opacity = float(0.5 + 0.5 * u01(rng));
        d.filter = (n % 2) ? TextureFilter::Linear : TextureFilter::Nearest;
        scene.decals.push_back(d);
    }
    return scene;
}

}  // namespace decalcomp::synth

namespace decalcomp::synth {

void convertDecals(DecalScene& scene, DecalKind kind, std::uint32_t seed) {
    if (kind == DecalKind::Box || scene.decals.empty()) return;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int texture = -1;
    if (kind == DecalKind::Volume || kind == DecalKind::Cube) {
        const int depth = kind == DecalKind::Volume ? 32 : 6;
        Texture2D t;
        t.source = "procedural";
        t.width = t.height = 32;
        t.depth = depth;
        t.shape = kind == DecalKind::Volume ? TextureShape::Volume : TextureShape::Cube;
        for (int k = 0; k < depth; ++k) {
            const Texture2D slice = proceduralTexture(k, 32, seed + std::uint32_t(k));
            t.texels.insert(t.texels.end(), slice.texels.begin(), slice.texels.end());
        }
        texture = int(scene.textures.size());
        scene.textures.push_back(std::move(t));
    }
    for (Decal& d : scene.decals) {
        d.kind = kind;
        if (texture >= 0) d.albedo_texture = texture;
        if (kind != DecalKind::Frustum) continue;
        const glm::dvec3 centre(d.world_matrix[3]);
        const double size = glm::length(glm::dvec3(d.world_matrix[0]));
        const glm::dvec3 origin = centre + glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + 1e-6) * (2.0 * size);
        d.world_matrix = glm::inverse(lookAt(origin, centre, glm::dvec3(u(rng), u(rng), 1.0)));
        d.fov_y_deg = 30.0;
        d.aspect = 1.0;
        d.near = 0.1 * size;
        d.far = 3.0 * size;
    }
}

}  // namespace decalcomp::synth
