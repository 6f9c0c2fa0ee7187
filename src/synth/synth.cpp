#include "decalcomp/synth.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "decalcomp/geometry.hpp"

namespace decalcomp::synth {

namespace {

struct Hit {
    double t = std::numeric_limits<double>::infinity();
    glm::dvec3 normal{0.0};
    int material = -1;
};

void intersectSphere(const Sphere& s, glm::dvec3 o, glm::dvec3 d, double t_min, Hit& hit) {
    const glm::dvec3 oc = o - s.center;
    const double b = glm::dot(oc, d), c = glm::dot(oc, oc) - s.radius * s.radius;
    const double disc = b * b - glm::dot(d, d) * c;
    if (disc < 0) return;
    const double sq = std::sqrt(disc), a = glm::dot(d, d);
    for (double t : {(-b - sq) / a, (-b + sq) / a})
        if (t > t_min && t < hit.t) {
            hit = {t, glm::normalize(o + d * t - s.center), s.material};
            return;
        }
}

void intersectPlane(const InfinitePlane& p, glm::dvec3 o, glm::dvec3 d, double t_min, Hit& hit) {
    const double denom = glm::dot(p.normal, d);
    if (std::abs(denom) < 1e-12) return;
    const double t = glm::dot(p.point - o, p.normal) / denom;
    if (t > t_min && t < hit.t) hit = {t, glm::normalize(p.normal), p.material};
}

// Slab test in the box's local space; an affine map keeps the ray parameter t.
void intersectBox(const Box& b, glm::dvec3 o, glm::dvec3 d, double t_min, Hit& hit) {
    const glm::dmat4 inv = glm::inverse(b.world_matrix);
    const glm::dvec3 lo = glm::dvec3(inv * glm::dvec4(o, 1.0)), ld = glm::dvec3(inv * glm::dvec4(d, 0.0));
    double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
    int axis0 = 0, axis1 = 0;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(ld[a]) < 1e-300) {
            if (std::abs(lo[a]) > 0.5) return;
            continue;
        }
        double ta = (-0.5 - lo[a]) / ld[a], tb = (0.5 - lo[a]) / ld[a];
        if (ta > tb) std::swap(ta, tb);
        if (ta > t0) t0 = ta, axis0 = a;
        if (tb < t1) t1 = tb, axis1 = a;
    }
    if (t0 > t1) return;
    const double t = t0 > t_min ? t0 : t1;
    const int axis = t0 > t_min ? axis0 : axis1;
    if (!(t > t_min) || t >= hit.t) return;
    glm::dvec3 local_normal(0.0);
    local_normal[axis] = (lo[axis] + ld[axis] * t) > 0 ? 1.0 : -1.0;
    const glm::dvec3 n = glm::transpose(glm::dmat3(inv)) * local_normal;
    hit = {t, glm::normalize(n), b.material};
}

glm::vec3 shadeAlbedo(const Material& m, glm::dvec3 p) {
    const long cell = long(std::floor(p.x / m.checker_size)) + long(std::floor(p.y / m.checker_size)) +
                      long(std::floor(p.z / m.checker_size));
    return (cell & 1) ? m.albedo_alt : m.albedo;
}

}  // namespace

GBuffer render(const Scene& scene, const Camera& camera, const RenderOptions& options) {
    GBuffer g;
    g.width = options.width;
    g.height = options.height;
    g.display_width = options.display_width > 0 ? options.display_width : options.width;
    g.display_height = options.display_height > 0 ? options.display_height : options.height;
    g.origin_x = options.origin_x;
    g.origin_y = options.origin_y;
    g.depth_convention = options.depth;
    g.reversed_z = options.reversed_z;
    const std::size_t n = g.pixelCount();
    auto make = [&](Attribute a) -> Plane& {
        Plane& p = g.planes[a];
        p.components = attributeComponents(a);
        p.samples.assign(n * p.components, 0.0f);
        return p;
    };
    Plane* depth = options.with_depth || options.depth != DepthConvention::Position ? &make(Attribute::Depth) : nullptr;
    Plane& albedo = make(Attribute::Albedo);
    Plane& normal = make(Attribute::Normal);
    Plane& position = make(Attribute::Position);
    Plane& id = make(Attribute::ObjectId);
    Plane& roughness = make(Attribute::Roughness);
    Plane& metallic = make(Attribute::Metallic);

    const glm::dmat4 camera_to_world = glm::inverse(camera.world_to_camera);
    const glm::dmat4 inverse_projection = glm::inverse(camera.projection);
    const bool ortho = camera.isOrthographic();
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const glm::dvec2 ndc = pixelNdc(g, x, y);
            const glm::dvec3 near_cam = unprojectNdc(inverse_projection, ndc, -1.0);
            const glm::dvec3 far_cam = unprojectNdc(inverse_projection, ndc, 0.0);  // finite if far = inf
            const glm::dvec3 origin_cam = ortho ? near_cam : glm::dvec3(0.0);
            const glm::dvec3 o = glm::dvec3(camera_to_world * glm::dvec4(origin_cam, 1.0));
            const glm::dvec3 dir = glm::normalize(glm::dvec3(camera_to_world * glm::dvec4(far_cam - near_cam, 0.0)));
            Hit hit;
            const double t_min = ortho ? 0.0 : glm::length(near_cam);  // nothing before the near plane
            for (const auto& s : scene.spheres) intersectSphere(s, o, dir, t_min, hit);
            for (const auto& p : scene.planes) intersectPlane(p, o, dir, t_min, hit);
            for (const auto& b : scene.boxes) intersectBox(b, o, dir, t_min, hit);
            const std::size_t i = std::size_t(y) * g.width + x;
            glm::dvec3 p_world = o + dir * hit.t;
            glm::dvec3 p_cam = glm::dvec3(camera.world_to_camera * glm::dvec4(p_world, 1.0));
            const bool background = hit.material < 0 || -p_cam.z > camera.farPlane();
            if (depth) {
                double d = kBackgroundDepth;
                if (!background) {
                    switch (options.depth) {
                        case DepthConvention::Planar:
                        case DepthConvention::Position: d = -p_cam.z; break;
                        case DepthConvention::Radial: d = ortho ? -p_cam.z : glm::length(p_cam); break;
                        case DepthConvention::Ndc: {
                            const glm::dvec4 c = camera.projection * glm::dvec4(p_cam, 1.0);
                            d = (c.z / c.w + 1.0) * 0.5;
                            if (options.reversed_z) d = 1.0 - d;
                        } break;
                    }
                } else if (options.depth == DepthConvention::Ndc) {
                    d = options.reversed_z ? 0.0 : 1.0;
                }
                depth->at(i, 0) = float(d);
            }
            if (background) {
                if (!depth) position.at(i, 0) = position.at(i, 1) = position.at(i, 2) = std::nanf("");
                continue;
            }
            const Material& m = scene.materials[std::size_t(hit.material)];
            glm::dvec3 nrm = hit.normal;
            if (glm::dot(nrm, dir) > 0) nrm = -nrm;  // face the camera
            // checker cells from a point just inside the surface: on a plane through a cell
            // boundary (the floor at z = 0) rounding would otherwise speckle the pattern
            const glm::vec3 a = shadeAlbedo(m, p_world - nrm * 1e-6);
            for (int c = 0; c < 3; ++c) {
                albedo.at(i, c) = a[c];
                normal.at(i, c) = float(nrm[c]);
                position.at(i, c) = float(p_world[c]);
            }
            id.at(i, 0) = float(m.object_id);
            roughness.at(i, 0) = m.roughness;
            metallic.at(i, 0) = m.metallic;
        }
    return g;
}

Scene demoScene() {
    Scene s;
    s.materials = {
        {{0.60f, 0.58f, 0.55f}, {0.45f, 0.43f, 0.40f}, 1.0, 0.8f, 0.0f, 1},  // floor, checker
        {{0.70f, 0.66f, 0.60f}, {0.70f, 0.66f, 0.60f}, 1.0, 0.9f, 0.0f, 2},  // wall
        {{0.20f, 0.35f, 0.60f}, {0.20f, 0.35f, 0.60f}, 1.0, 0.3f, 0.0f, 3},  // sphere
        {{0.55f, 0.25f, 0.15f}, {0.55f, 0.25f, 0.15f}, 1.0, 0.5f, 0.0f, 4},  // box
    };
    s.planes = {{{0, 0, 0}, {0, 0, 1}, 0}, {{0, 3, 0}, {0, -1, 0}, 1}};
    s.spheres = {{{-1.2, 0.2, 1.0}, 1.0, 2}};
    glm::dmat4 box(1.0);
    box = glm::translate(box, glm::dvec3(1.4, 0.6, 0.6));
    box = glm::rotate(box, 0.5, glm::dvec3(0, 0, 1));
    box = glm::scale(box, glm::dvec3(1.2, 1.2, 1.2));
    s.boxes = {{box, 3}};
    return s;
}

Camera demoCamera(int width, int height) {
    Camera c;
    c.world_to_camera = lookAt({1.0, -5.2, 3.0}, {0.2, 1.0, 0.8}, {0, 0, 1});
    c.projection = perspectiveProjection(glm::radians(50.0), double(width) / height, 0.1, 100.0);
    c.source = "synthetic demo camera";
    return c;
}

Scene randomScene(std::uint32_t seed, double extent) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
    Scene s;
    for (int m = 0; m < 8; ++m) {
        const glm::vec3 a(float(u01(rng)), float(u01(rng)), float(u01(rng)));
        const glm::vec3 b(float(u01(rng)), float(u01(rng)), float(u01(rng)));
        s.materials.push_back({a, b, 0.3 + u01(rng) * extent * 0.2, float(u01(rng)), float(u01(rng)), m + 1});
    }
    auto material = [&] { return int(rng() % s.materials.size()); };
    auto direction = [&] {
        glm::dvec3 v(u(rng), u(rng), u(rng));
        return glm::length(v) < 1e-3 ? glm::dvec3(0, 0, 1) : glm::normalize(v);
    };
    for (int i = 0; i < 2; ++i) s.planes.push_back({direction() * (extent * (0.5 + 0.5 * u01(rng))), direction(), material()});
    for (int i = 0; i < 6; ++i)
        s.spheres.push_back({glm::dvec3(u(rng), u(rng), u(rng)) * extent * 0.6, extent * (0.05 + 0.2 * u01(rng)), material()});
    for (int i = 0; i < 6; ++i) {
        glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(u(rng), u(rng), u(rng)) * extent * 0.6);
        m = glm::rotate(m, u(rng) * 3.14159, direction());
        m = glm::scale(m, glm::dvec3(0.1 + u01(rng), 0.1 + u01(rng), 0.1 + u01(rng)) * extent * 0.4);
        s.boxes.push_back({m, material()});
    }
    return s;
}

}  // namespace decalcomp::synth
