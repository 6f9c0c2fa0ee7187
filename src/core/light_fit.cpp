// The relight approximation's light: a least-squares fit of the direct light's luminance against
// the world normal, luminance ~ w + dot(c, n), over the lit pixels. For one distant light and no
// shadows it recovers c = E * direction; shadows and several lights make it an average.
#include <glm/glm.hpp>

#include <cmath>

#include "decalcomp/beauty.hpp"
#include "decalcomp/normal_codec.hpp"

namespace decalcomp {

namespace {

double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// The light at one pixel, divided by the albedo when it is multiplied by it; < 0: unusable.
double lightAt(const std::vector<const Plane*>& direct, bool divided, const Plane& albedo, std::size_t i) {
    double r = 0, g = 0, b = 0;
    for (const Plane* term : direct) r += term->at(i, 0), g += term->at(i, 1), b += term->at(i, 2);
    if (divided) return luminance(r, g, b);
    const double a = luminance(albedo.at(i, 0), albedo.at(i, 1), albedo.at(i, 2));
    return a > 1e-4 ? luminance(r, g, b) / a : -1.0;
}

}  // namespace

LightFit fitDirectLight(const std::vector<const Plane*>& direct, bool divided, const GBuffer& frame,
                        const Camera& camera, std::size_t step) {
    LightFit fit;
    if (direct.empty() || !frame.has(Attribute::Normal) || !frame.has(Attribute::Albedo)) return fit;
    const Plane& normals = frame.planes.at(Attribute::Normal);
    const Plane& albedo = frame.planes.at(Attribute::Albedo);
    const NormalCodec codec(frame.normal_encoding, camera);
    glm::dmat4 normal_matrix(0.0);
    glm::dvec4 rhs(0.0);
    std::vector<std::pair<glm::dvec4, double>> used;
    step = std::max<std::size_t>(step, 1);
    for (std::size_t i = 0; i < frame.pixelCount(); i += step) {
        const double light = lightAt(direct, divided, albedo, i);
        if (!(light > 1e-4) || !std::isfinite(light)) continue;  // shadowed pixels say nothing of the direction
        glm::vec3 stored(0.0f);
        for (int c = 0; c < std::min(normals.components, 3); ++c) stored[c] = normals.at(i, c);
        const glm::dvec3 n(codec.toWorld(stored));
        const double length = glm::length(n);
        if (!(length > 0.5)) continue;
        const glm::dvec4 x(1.0, n / length);
        normal_matrix += glm::outerProduct(x, x);
        rhs += x * light;
        used.emplace_back(x, light);
    }
    if (used.size() < 16 || std::abs(glm::determinant(normal_matrix)) < 1e-12) return fit;
    const glm::dvec4 solution = glm::inverse(normal_matrix) * rhs;
    fit.w = float(solution.x);
    fit.c[0] = float(solution.y), fit.c[1] = float(solution.z), fit.c[2] = float(solution.w);
    double squares = 0;
    for (const auto& [x, light] : used) {
        const double residual = glm::dot(x, solution) - light;
        squares += residual * residual;
    }
    fit.pixels = used.size();
    fit.rms = std::sqrt(squares / double(used.size()));
    return fit;
}

}  // namespace decalcomp
