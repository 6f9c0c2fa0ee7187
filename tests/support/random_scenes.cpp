// Random frames and decal scenes for kernel-vs-reference tests (moved from test_kernels.cpp so
// several test files share them).
#include "support/random_scenes.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "decalcomp/synth.hpp"

namespace decalcomp::test {

ComputeDevice& cpuDevice() {
    static ComputeDevice device("cpu");
    return device;
}

RandomFrame makeRandomFrame(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
    RandomFrame f;
    f.scene = synth::randomScene(seed, 10.0);
    const glm::dvec3 eye(u(rng) * 8, u(rng) * 8, u(rng) * 8);
    const glm::dvec3 target(u(rng) * 2, u(rng) * 2, u(rng) * 2);
    f.camera.world_to_camera = lookAt(eye, target, glm::dvec3(u(rng), u(rng), 1.0));
    const int width = 61 + int(rng() % 60), height = 41 + int(rng() % 50);  // not tile multiples
    const double aspect = double(width) / height;
    const bool ortho = seed % 5 == 4;
    f.camera.projection = ortho ? orthographicProjection(3.0 + 5 * u01(rng), aspect, -20.0, 60.0)
                                : perspectiveProjection(glm::radians(20.0 + 90.0 * u01(rng)), aspect,
                                                        0.05 + 0.3 * u01(rng), 80.0, 0.2 * u(rng), 0.2 * u(rng));
    synth::RenderOptions options;
    options.width = width;
    options.height = height;
    const DepthConvention conventions[] = {DepthConvention::Planar, DepthConvention::Radial, DepthConvention::Ndc,
                                           DepthConvention::Position};
    options.depth = conventions[seed % 4];
    options.reversed_z = options.depth == DepthConvention::Ndc && (seed / 4) % 2 == 1;
    f.gbuffer = synth::render(f.scene, f.camera, options);
    return f;
}

// Random premultiplied texels: alpha in [0,1], colour <= alpha.
Texture2D randomTexture(int width, int height, int depth, std::mt19937& rng, TextureShape shape) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Texture2D t;
    t.source = "random";
    t.width = width;
    t.height = height;
    t.depth = depth;
    t.shape = shape;
    for (int i = 0; i < width * height * depth; ++i) {
        const float a = u(rng);
        t.texels.emplace_back(u(rng) * a, u(rng) * a, u(rng) * a, a);
    }
    return t;
}

namespace {

// Turns scattered box decals into every kind, and switches fades on at random.
void convertKinds(DecalScene& scene, const RandomFrame& f, std::uint32_t seed) {
    std::mt19937 rng(seed * 31 + 7);
    std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
    const int volume = int(scene.textures.size());
    scene.textures.push_back(randomTexture(6, 6, 5, rng, TextureShape::Volume));
    const int cube = int(scene.textures.size());
    scene.textures.push_back(randomTexture(7, 7, 6, rng, TextureShape::Cube));
    const bool normals = f.gbuffer.has(Attribute::Normal);
    for (std::size_t k = 0; k < scene.decals.size(); ++k) {
        Decal& d = scene.decals[k];
        // scattered decals are centred on pixel centres: move them off, or the frustum's and the
        // cube's centre rays would sit exactly on texel edges and on the cube's singular centre
        const glm::dvec3 centre = glm::dvec3(d.world_matrix[3]) + glm::dvec3(u(rng), u(rng), u(rng)) * 0.05;
        switch (k % 4) {
            case 1:
                d.kind = DecalKind::Volume;
                d.albedo_texture = volume;
                break;
            case 2: {
                // a rigid projector a few units from the surface point, looking at it
                d.kind = DecalKind::Frustum;
                const glm::dvec3 origin = centre + glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + 1e-6) * (1.0 + 4.0 * u01(rng));
                d.world_matrix = glm::inverse(lookAt(origin, centre, glm::dvec3(u(rng), u(rng), 1.0)));
                d.fov_y_deg = 15.0 + 60.0 * u01(rng);
                d.aspect = 0.5 + 1.5 * u01(rng);
                d.near = 0.05 + 0.5 * u01(rng);
                d.far = glm::length(origin - centre) * (1.0 + u01(rng));
                if (k % 8 == 2) d.distance_fade = {d.far * 0.3, d.far * 0.9};
                break;
            }
            case 3:
                d.kind = DecalKind::Cube;
                d.albedo_texture = cube;
                d.world_matrix[3] = glm::dvec4(centre, 1.0);
                break;
            default:
                break;
        }
        if (normals && k % 3 == 0) d.angle_fade_deg = {10.0 + 30.0 * u01(rng), 50.0 + 60.0 * u01(rng)};
        if (k % 5 == 0) d.axis_fade = 0.2 + 0.6 * u01(rng);
        if (k % 7 == 3) d.filter = TextureFilter::Mip;
    }
}

}  // namespace

// Hundreds of decals: scattered on surfaces plus the hard cases, all in one scene.
DecalScene makeRandomDecals(const RandomFrame& f, std::uint32_t seed, int count) {
    synth::ScatterOptions scatter;
    scatter.count = count;
    scatter.min_size = 0.3;
    scatter.max_size = 6.0;
    scatter.texture_size = 8 + int(seed % 3) * 12;
    scatter.seed = seed;
    DecalScene scene = synth::scatterDecals(f.gbuffer, f.camera, scatter);
    std::mt19937 rng(seed + 17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const glm::dmat4 camera_to_world = glm::inverse(f.camera.world_to_camera);
    const glm::dvec3 eye(camera_to_world[3]);
    const glm::dvec3 forward = -glm::dvec3(camera_to_world[2]);
    auto add = [&](const std::string& name, glm::dmat4 m) {
        Decal d;
        d.name = name;
        d.world_matrix = m;
        d.albedo_texture = int(rng() % scene.textures.size());
        d.opacity = 0.7f;
        d.filter = rng() % 2 ? TextureFilter::Linear : TextureFilter::Nearest;
        scene.decals.insert(scene.decals.begin() + std::ptrdiff_t(rng() % (scene.decals.size() + 1)), d);
    };
    auto rotated = [&](glm::dvec3 centre, glm::dvec3 size) {
        glm::dmat4 m = glm::translate(glm::dmat4(1.0), centre);
        m = glm::rotate(m, u(rng) * 3.0, glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + 1e-6));
        return glm::scale(m, size);
    };
    convertKinds(scene, f, seed);
    add("camera_inside", rotated(eye, glm::dvec3(6.0, 5.0, 7.0)));
    add("crossing_near_plane", rotated(eye + forward * 0.3, glm::dvec3(2.0, 2.0, 2.0)));
    add("behind_camera", rotated(eye - forward * 4.0, glm::dvec3(1.5)));
    add("huge", rotated(glm::dvec3(0.0), glm::dvec3(300.0, 250.0, 40.0)));
    add("thin", rotated(eye + forward * 6.0, glm::dvec3(3.0, 3.0, 1e-3)));
    add("needle", rotated(eye + forward * 5.0, glm::dvec3(1e-3, 1e-3, 8.0)));
    add("tiny", rotated(eye + forward * 5.0, glm::dvec3(1e-4)));
    return scene;
}

Comparison compareWithReference(const GBuffer& input, const GBuffer& output, const reference::ShadeResult& ref,
                                double tolerance) {
    Comparison c;
    const Plane& in = input.planes.at(Attribute::Albedo);
    const Plane& out = output.planes.at(Attribute::Albedo);
    for (std::size_t i = 0; i < input.pixelCount(); ++i) {
        bool changed = false;
        for (int ch = 0; ch < 3; ++ch) changed |= ref.albedo.at(i, ch) != in.at(i, ch);
        c.changed += changed;
        if (ref.ambiguous[i]) {
            ++c.ambiguous;
            continue;
        }
        ++c.compared;
        double error = 0;
        for (int ch = 0; ch < 3; ++ch) error = std::max(error, double(std::abs(out.at(i, ch) - ref.albedo.at(i, ch))));
        c.max_error = std::max(c.max_error, error);
        if (error > tolerance) {
            ++c.mismatched;
        }
    }
    return c;
}

double roundingMargin(const GBuffer& g) { return g.depth_convention == DepthConvention::Ndc ? 5e-6 : 5e-7; }

// Tolerance: float vs double over hundreds of blends, bilinear weights and fade ramps drifts far
// less than this; hardware (ndc) depth reconstructs positions less exactly, so it gets more.
namespace {
constexpr double kAlbedoTolerance = 1e-3;
}
double albedoTolerance(const GBuffer& g) { return g.depth_convention == DepthConvention::Ndc ? 5e-3 : kAlbedoTolerance; }
// Share of pixels allowed within rounding of a decision (box face, texel edge, cube face).
double ambiguousShare(const GBuffer& g) { return g.depth_convention == DepthConvention::Ndc ? 0.25 : 0.10; }

// Composites on PoCL and compares with the scalar reference at the frame's stated tolerance.
std::pair<GBuffer, Comparison> compositeAndCompare(const RandomFrame& f, const DecalScene& decals) {
    Compositor compositor(cpuDevice());
    compositor.setScene(decals);
    GBuffer out = f.gbuffer;
    compositor.composite(out, f.camera);
    const auto ref = reference::shade(f.gbuffer, f.camera, decals, roundingMargin(f.gbuffer));
    return {out, compareWithReference(f.gbuffer, out, ref, albedoTolerance(f.gbuffer))};
}

Comparison expectFilteredKernelMatchesReference(const RandomFrame& f, const DecalScene& decals) {
    const auto [out, c] = compositeAndCompare(f, decals);
    EXPECT_EQ(c.mismatched, 0u) << f.gbuffer.pixel_filter.spelling() << ": max error " << c.max_error << " over "
                                << c.compared << " pixels";
    const double allowed = std::min(0.5, 2.5 * ambiguousShare(f.gbuffer));
    EXPECT_LT(double(c.ambiguous), allowed * double(f.gbuffer.pixelCount()))
        << depthConventionName(f.gbuffer.depth_convention) << " " << f.gbuffer.width << "x" << f.gbuffer.height;
    EXPECT_GT(double(c.changed), 0.05 * double(f.gbuffer.pixelCount()));
    return c;
}

std::size_t binnedUnbinnedDifferences(const RandomFrame& f, const DecalScene& decals) {
    Compositor compositor(cpuDevice());
    compositor.setScene(decals);
    GBuffer binned = f.gbuffer, unbinned = f.gbuffer;
    compositor.composite(binned, f.camera, {true});
    compositor.composite(unbinned, f.camera, {false});
    const auto& a = binned.planes.at(Attribute::Albedo).samples;
    const auto& b = unbinned.planes.at(Attribute::Albedo).samples;
    std::size_t differing = a.size() == b.size() ? 0 : a.size() + b.size();
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) differing += std::memcmp(&a[i], &b[i], sizeof(float)) != 0;
    return differing;
}

}  // namespace decalcomp::test
