#include "texture_space.hpp"

#include "median.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "decalcomp/synth.hpp"
#include "decalcomp/synth_mesh.hpp"

namespace decalcomp::bench {

Timing timeFrames(Compositor& compositor, const DecalScene& scene, const GBuffer& frame, const Camera& camera, int repeat) {
    compositor.setScene(scene);
    GBuffer work = frame;
    compositor.composite(work, camera);  // warm-up
    Timing t;
    const Plane& before = frame.planes.at(Attribute::Albedo);
    for (std::size_t i = 0; i < frame.pixelCount(); ++i)
        t.changed += work.planes.at(Attribute::Albedo).at(i, 0) != before.at(i, 0);
    std::vector<double> kernel, rest, shading, wall;
    for (int r = 0; r < repeat; ++r) {
        work.planes.at(Attribute::Albedo) = before;
        const auto t0 = std::chrono::steady_clock::now();
        const CompositeStats s = compositor.composite(work, camera);
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        kernel.push_back(s.totalKernelMs());
        rest.push_back(s.rest_ms);
        shading.push_back(s.shading_ms);
    }
    return {median(kernel), median(rest), median(shading), median(wall), t.changed};
}

TubeBench tubeBench(int width, int height) {
    TubeBench b;
    b.tube = synth::tubeMesh(256, 200);  // 102,400 triangles
    const RestMesh& tube = b.tube;
    Camera& camera = b.camera;
    camera.world_to_camera = lookAt({3.4, -0.5, 1.0}, {0.0, 0.0, 1.0}, {0, 0, 1});
    camera.projection = perspectiveProjection(0.7, double(width) / height, 0.1, 100.0);
    std::vector<synth::PosedMesh> meshes(1);
    meshes[0] = {&tube, {}, 1, glm::vec3(0.6f)};
    for (const RestVertex& v : tube.vertices) meshes[0].positions.push_back(v.position);
    b.frame = synth::renderMeshes(meshes, camera, width, height).gbuffer;
    GBuffer& frame = b.frame;
    for (Attribute a : {Attribute::Normal, Attribute::Position}) frame.planes.erase(a);
    Plane mask{1, std::vector<float>(frame.pixelCount())};
    for (std::size_t i = 0; i < frame.pixelCount(); ++i) mask.samples[i] = frame.planes.at(Attribute::ObjectId).at(i, 0);
    frame.mask_weights = {mask};

    // A box through the tube's front, facing the camera's side (+X), 0.8 around by 1.6 up.
    DecalScene& scene = b.scene;
    scene.meshes = {tube};
    DecalMask object;
    object.include_ids = {1};
    scene.masks = {object};
    scene.textures = {synth::proceduralTexture(1, 64, 5)};
    Decal box;
    box.name = "label";
    box.albedo_texture = 0;
    box.mask = 0;
    box.filter = TextureFilter::Linear;
    box.world_matrix = glm::dmat4(glm::dvec4(0, 0.8, 0, 0), glm::dvec4(0, 0, 1.6, 0), glm::dvec4(0.6, 0, 0, 0),
                                  glm::dvec4(0.5, 0, 1.0, 1));
    scene.decals = {box};
    return b;
}

void benchTextureSpace(Compositor& compositor, int width, int height, int repeat, std::FILE* out) {
    TubeBench b = tubeBench(width, height);
    DecalScene& scene = b.scene;
    const Timing world = timeFrames(compositor, scene, b.frame, b.camera, repeat);
    scene.decals[0].space = DecalSpace::ObjectRest;
    scene.decals[0].rest_mesh = 0;
    const Timing rest = timeFrames(compositor, scene, b.frame, b.camera, repeat);
    fmt::print(out, "\ntexture space, {}x{}, {} triangles, the decal on {} pixels ({} world):\n", width, height,
               b.tube.triangles.size(), rest.changed, world.changed);
    fmt::print(out, "  world box:          kernels {:.3f} ms (shading {:.3f}), composite() {:.2f} ms\n", world.kernel_ms,
               world.shading_ms, world.wall_ms);
    fmt::print(out, "  texture-space box:  kernels {:.3f} ms (rest pass {:.3f}, shading {:.3f}), composite() {:.2f} ms\n",
               rest.kernel_ms, rest.rest_ms, rest.shading_ms, rest.wall_ms);
    fmt::print(out, "  texture space / world: kernels {:.2f}x, composite() {:.2f}x\n",
               world.kernel_ms > 0 ? rest.kernel_ms / world.kernel_ms : 0.0, rest.wall_ms / world.wall_ms);
}

}  // namespace decalcomp::bench
