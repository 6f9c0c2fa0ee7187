#pragma once
// Analytic scenes (planes, boxes, spheres) ray-cast into G-buffers with exact depth, for tests,
// the sample data and benchmarks.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp::synth {

struct Material {
    glm::vec3 albedo{0.5f};
    glm::vec3 albedo_alt{0.5f};  // second colour of a world-space checker (same as albedo = plain)
    double checker_size = 1.0;
    float roughness = 0.5f, metallic = 0.0f;
    int object_id = 0;
};

struct Sphere {
    glm::dvec3 center{0.0};
    double radius = 1.0;
    int material = 0;
};
struct InfinitePlane {
    glm::dvec3 point{0.0}, normal{0, 0, 1};
    int material = 0;
};
struct Box {
    glm::dmat4 world_matrix{1.0};  // maps the unit box [-0.5, 0.5]^3
    int material = 0;
};

struct Scene {
    std::vector<Material> materials;
    std::vector<Sphere> spheres;
    std::vector<InfinitePlane> planes;
    std::vector<Box> boxes;
};

struct RenderOptions {
    int width = 320, height = 240;
    DepthConvention depth = DepthConvention::Planar;  // Position: position pass drives, depth kept too
    bool reversed_z = false;
    bool with_depth = true;  // false drops the depth pass (only with DepthConvention::Position)
    // The rendered pixels as a data window of a larger (or smaller) display window: pixel (x, y)
    // is display pixel (x + origin_x, y + origin_y). 0 x 0 display = width x height (full frame).
    int origin_x = 0, origin_y = 0;
    int display_width = 0, display_height = 0;
};

// Planes produced: depth (in the chosen convention; background 1e10, or 1 / 0 for ndc), albedo,
// normal (world), position (world; 0 on background), object_id, roughness, metallic.
GBuffer render(const Scene& scene, const Camera& camera, const RenderOptions& options);

// A floor, a back wall, a sphere and a box, seen by demoCamera.
Scene demoScene();
Camera demoCamera(int width, int height);

// Random spheres, boxes and planes around the origin within about `extent` units.
Scene randomScene(std::uint32_t seed, double extent = 10.0);

}  // namespace decalcomp::synth

#include "decalcomp/decal.hpp"

namespace decalcomp::synth {

struct ScatterOptions {
    int count = 64;
    double min_size = 0.2, max_size = 1.0;  // world units, box edge lengths
    int texture_count = 4;
    int texture_size = 32;
    std::uint32_t seed = 1;
    int first_row = 0, last_row = -1;  // centres on pixels of these rows only (-1: the last row)
};

// Procedural RGBA decal textures (rings, checkers, spots) in linear premultiplied colour.
Texture2D proceduralTexture(int kind, int size, std::uint32_t seed);

// Decals centred on random visible surface points of the frame, random orientation and size,
// each with one of `texture_count` procedural textures, alternating nearest and linear filtering.
DecalScene scatterDecals(const GBuffer& frame, const Camera& camera, const ScatterOptions& options);

}  // namespace decalcomp::synth

namespace decalcomp::synth {

// Turns every decal of a scattered scene into `kind`, keeping its centre and size: volumes get a
// procedural 32^3 texture, cubes six procedural faces, frustums become projectors a little in
// front of the surface point looking at it. For benchmarks of each kind.
void convertDecals(DecalScene& scene, DecalKind kind, std::uint32_t seed);

}  // namespace decalcomp::synth
