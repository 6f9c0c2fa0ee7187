// Kernels on PoCL's CPU device against the scalar reference (src/reference), on random scenes.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>

#include "decalcomp/compositor.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/reference.hpp"
#include "decalcomp/synth.hpp"
#include "shared_types.h"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

using test::Comparison;
using test::RandomFrame;
using test::albedoTolerance;
using test::ambiguousShare;
using test::compareWithReference;
using test::compositeAndCompare;
using test::cpuDevice;
using test::makeRandomDecals;
using test::makeRandomFrame;
using test::randomTexture;
using test::roundingMargin;

class RandomScenes : public ::testing::TestWithParam<std::uint32_t> {};

// Composites once and returns the tile depth ranges and lists the binning produced.
BinningResult binRandomScene(const RandomFrame& f, const DecalScene& decals) {
    Compositor compositor(cpuDevice());
    compositor.setScene(decals);
    GBuffer out = f.gbuffer;
    compositor.composite(out, f.camera);
    return compositor.lastBinning();
}

TEST_P(RandomScenes, BinnedKernelMatchesReference) {
    const RandomFrame f = makeRandomFrame(GetParam());
    const DecalScene decals = makeRandomDecals(f, GetParam(), 300);
    const auto [out, c] = compositeAndCompare(f, decals);
    EXPECT_EQ(c.mismatched, 0u) << "max error " << c.max_error << " over " << c.compared << " pixels";
    // Each nearest decal centred on a surface point puts that pixel exactly on a texel edge, so a
    // few percent of pixels are legitimately ambiguous; more would make the comparison hollow.
    EXPECT_LT(double(c.ambiguous), ambiguousShare(f.gbuffer) * double(f.gbuffer.pixelCount()))
        << "too many boundary pixels to be meaningful";
    EXPECT_GT(double(c.changed), 0.05 * double(f.gbuffer.pixelCount())) << "scene decals too few pixels to test";
}

TEST_P(RandomScenes, BinnedEqualsUnbinnedExactly) {
    const RandomFrame f = makeRandomFrame(GetParam());
    EXPECT_EQ(test::binnedUnbinnedDifferences(f, makeRandomDecals(f, GetParam(), 300)), 0u)
        << "binning dropped or reordered decals for some pixels";
}

// Many small decals centred on a band of rows: their tiles list more than the 256 entries the
// point kernels stage in local memory (shading.cl dc_stage_list), and each entry's pixel range
// holds few of its tile's pixels.
DecalScene smallDecalsOnABand(const RandomFrame& f, std::uint32_t seed) {
    synth::ScatterOptions scatter;
    scatter.count = 2000;
    scatter.min_size = 0.05;
    scatter.max_size = 0.5;
    scatter.texture_size = 8;
    scatter.seed = seed;
    scatter.first_row = f.gbuffer.height / 3;
    scatter.last_row = f.gbuffer.height / 3 + 8;
    return synth::scatterDecals(f.gbuffer, f.camera, scatter);
}

TEST_P(RandomScenes, SmallDecalsBeyondTheStagedEntriesMatchReferenceAndUnbinned) {
    const RandomFrame f = makeRandomFrame(GetParam());
    const DecalScene decals = smallDecalsOnABand(f, GetParam());
    const BinningResult bins = binRandomScene(f, decals);
    int longest = 0, listed_tiles = 0;
    for (std::size_t t = 0; t + 1 < bins.tile_offsets.size(); ++t) {
        const int length = bins.tile_offsets[t + 1] - bins.tile_offsets[t];
        longest = std::max(longest, length);
        listed_tiles += length > 0;
    }
    ASSERT_GT(longest, 256) << "no tile lists more entries than the kernels stage";
    const auto [out, c] = compositeAndCompare(f, decals);
    EXPECT_EQ(c.mismatched, 0u) << "max error " << c.max_error << " over " << c.compared << " pixels";
    EXPECT_GT(c.changed, 0u);
    // the decals are small: their listed tiles hold many pixels none of them reaches
    EXPECT_LT(double(c.changed), 0.9 * listed_tiles * DC_TILE_SIZE * DC_TILE_SIZE);
    EXPECT_EQ(test::binnedUnbinnedDifferences(f, decals), 0u) << "binning dropped or reordered decals for some pixels";
}

// How far the kernel's float view depth may be from the double reference at view depth z. With
// NDC depth the conversion z(ndc) is ill-conditioned near the far plane: one float rounding of the
// NDC-to-view arithmetic moves z by |dz/dndc| * FLT_EPSILON, where (OpenGL projection)
// dz/dndc = (f - n) z^2 / (2 f n) in perspective and (f - n) / 2 in orthographic. Four roundings'
// worth; other conventions store view distances, where 1e-5 relative is plenty.
double tileDepthTolerance(const RandomFrame& f, double z) {
    const double relative = 1e-5 * (1 + z);
    if (f.gbuffer.depth_convention != DepthConvention::Ndc) return relative;
    const double n = f.camera.nearPlane(), far = f.camera.farPlane();
    const double slope = f.camera.isOrthographic() ? (far - n) / 2
                         : std::isinf(far)         ? z * z / (2 * n)
                                                   : (far - n) * z * z / (2 * far * n);
    return relative + 4 * slope * double(FLT_EPSILON);
}

TEST_P(RandomScenes, TileDepthRangesMatchReference) {
    const RandomFrame f = makeRandomFrame(GetParam());
    const BinningResult bins = binRandomScene(f, makeRandomDecals(f, GetParam(), 20));
    const auto ref = reference::tileDepthRanges(f.gbuffer, f.camera, DC_TILE_SIZE);
    ASSERT_EQ(bins.tile_depth.size(), ref.size() * 2);
    std::size_t non_empty = 0;
    for (std::size_t t = 0; t < ref.size(); ++t) {
        const float lo = bins.tile_depth[2 * t], hi = bins.tile_depth[2 * t + 1];
        ASSERT_EQ(ref[t].empty, lo > hi) << "tile " << t;
        if (ref[t].empty) continue;
        ++non_empty;
        EXPECT_NEAR(lo, ref[t].min, tileDepthTolerance(f, ref[t].min)) << "tile " << t;
        EXPECT_NEAR(hi, ref[t].max, tileDepthTolerance(f, ref[t].max)) << "tile " << t;
    }
    EXPECT_GT(non_empty, 0u);
}

TEST_P(RandomScenes, BinningIsConservativeAndOrdered) {
    const RandomFrame f = makeRandomFrame(GetParam());
    const DecalScene decals = makeRandomDecals(f, GetParam(), 300);
    const BinningResult bins = binRandomScene(f, decals);
    const auto exact = reference::exactBins(f.gbuffer, f.camera, decals, DC_TILE_SIZE);
    ASSERT_EQ(bins.tile_offsets.size(), exact.size() + 1);
    std::size_t needed = 0, listed = 0;
    for (std::size_t t = 0; t < exact.size(); ++t) {
        const std::vector<int> got(bins.tile_decals.begin() + bins.tile_offsets[t],
                                   bins.tile_decals.begin() + bins.tile_offsets[t + 1]);
        EXPECT_TRUE(std::is_sorted(got.begin(), got.end())) << "tile " << t << " lost decal order";
        for (int d : exact[t])
            EXPECT_TRUE(std::binary_search(got.begin(), got.end(), d))
                << "tile " << t << " misses decal " << d << " (" << decals.decals[std::size_t(d)].name << ")";
        needed += exact[t].size();
        listed += got.size();
    }
    EXPECT_GT(needed, 0u);
    // Conservative but useful: the bins must not degenerate to "every decal everywhere".
    EXPECT_LE(listed, 3 * needed + exact.size());
}

INSTANTIATE_TEST_SUITE_P(Kernels, RandomScenes, ::testing::Range(1u, 13u));

TEST(Kernels, ProgramBuildsOnPocl) {
    EXPECT_NO_THROW(cpuDevice().program());
}

// The kernel names of a program, ';'-separated as OpenCL lists them, each between ';'.
std::string kernelNames(const cl::Program& program) { return ";" + program.getInfo<CL_PROGRAM_KERNEL_NAMES>() + ";"; }

// Point-sampled work builds a program without the shading kernels of filtered frames (a cold NVIDIA
// build of those took over 9 minutes); each of those comes from a program of its own variant and
// paths, built once.
TEST(Kernels, FilteredShadingKernelsComeFromProgramsOfTheirOwn) {
    ComputeDevice device("cpu");
    const std::string point = kernelNames(device.program());
    EXPECT_NE(point.find(";dc_shade_point;"), std::string::npos) << point;
    EXPECT_NE(point.find(";dc_bin_fill;"), std::string::npos) << point;
    EXPECT_EQ(point.find(";dc_shade;"), std::string::npos) << point;
    const ShadingPaths fast{false, true, false};
    EXPECT_EQ(kernelNames(device.shadingProgram(DC_VARIANT_FLAT, fast)), ";dc_shade;");
    EXPECT_EQ(device.shadingProgram(DC_VARIANT_FLAT, fast)(), device.shadingProgram(DC_VARIANT_FLAT, fast)());
    EXPECT_NE(device.shadingProgram(DC_VARIANT_FLAT, fast)(), device.shadingProgram(0, fast)());
    EXPECT_NE(device.shadingProgram(DC_VARIANT_FLAT, fast)(),
              device.shadingProgram(DC_VARIANT_FLAT, ShadingPaths{true, false, false})());
    EXPECT_EQ(kernelNames(device.program()), point);
    EXPECT_THROW(device.shadingProgram(DC_VARIANT_POINT, fast), Error);
}

// Compositors on worker threads share a device: two threads asking for the same shading program at
// once get one program, built once.
TEST(Kernels, ThreadsAskingForOneShadingProgramShareIt) {
    ComputeDevice device("cpu");
    const ShadingPaths taps{true, false, false};
    cl_program built[2] = {};
    std::thread other([&] { built[1] = device.shadingProgram(DC_VARIANT_ALBEDO_ONLY, taps)(); });
    built[0] = device.shadingProgram(DC_VARIANT_ALBEDO_ONLY, taps)();
    other.join();
    EXPECT_NE(built[0], nullptr);
    EXPECT_EQ(built[0], built[1]);
}

// A build still running after the notice's delay says so once, naming the device and the
// program; a build that finishes first says nothing, and does not wait out the delay.
TEST(Kernels, ABuildRunningLongSaysSoOnce) {
    std::mutex mutex;
    std::vector<std::string> notices;
    const auto collect = [&](const std::string& m) {
        const std::lock_guard lock(mutex);
        notices.push_back(m);
    };
    ComputeDevice device("cpu");
    device.setSlowBuildNotice(std::chrono::milliseconds(0), collect);
    device.program();
    device.program();  // built: no second build, no second notice
    ASSERT_EQ(notices.size(), 1u);
    EXPECT_NE(notices[0].find(device.info().name + ": still compiling the OpenCL kernels for binning and "
                                                   "point-sampled shading"),
              std::string::npos)
        << notices[0];
    device.shadingProgram(0, ShadingPaths{true, false, false});
    ASSERT_EQ(notices.size(), 2u);
    EXPECT_NE(notices[1].find("shading with the pixel filter's taps"), std::string::npos) << notices[1];

    ComputeDevice throwing("cpu");  // a notice that throws on its thread must not end the process
    throwing.setSlowBuildNotice(std::chrono::milliseconds(0),
                                [](const std::string&) { throw std::runtime_error("no stream"); });
    EXPECT_NE(throwing.program()(), nullptr);

    ComputeDevice patient("cpu");
    patient.setSlowBuildNotice(std::chrono::hours(1), collect);
    const auto start = std::chrono::steady_clock::now();
    patient.program();
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::minutes(5));
    EXPECT_EQ(notices.size(), 2u);
}

// One compositor, a point-sampled frame, then a filtered one (which needs a shading program it
// did not build yet), then the point-sampled frame again: each as a fresh compositor makes it.
TEST(Kernels, ACompositorTakesAShadingProgramWhenAFrameNeedsIt) {
    const RandomFrame f = makeRandomFrame(5);
    const DecalScene decals = makeRandomDecals(f, 5, 24);
    GBuffer filtered_frame = f.gbuffer;
    filtered_frame.pixel_filter = parsePixelFilter("blackman-harris:3", "");
    const auto alone = [&](const GBuffer& frame) {
        ComputeDevice device("cpu");
        Compositor compositor(device);
        compositor.setScene(decals);
        GBuffer out = frame;
        compositor.composite(out, f.camera);
        return out.planes.at(Attribute::Albedo).samples;
    };
    ComputeDevice device("cpu");
    Compositor compositor(device);
    compositor.setScene(decals);
    std::vector<std::vector<float>> in_turn;
    for (const GBuffer* frame : std::initializer_list<const GBuffer*>{&f.gbuffer, &filtered_frame, &f.gbuffer}) {
        GBuffer out = *frame;
        compositor.composite(out, f.camera);
        in_turn.push_back(out.planes.at(Attribute::Albedo).samples);
    }
    EXPECT_EQ(in_turn[0], alone(f.gbuffer));
    EXPECT_EQ(in_turn[1], alone(filtered_frame));
    EXPECT_EQ(in_turn[2], in_turn[0]);
    EXPECT_NE(in_turn[1], in_turn[0]) << "the filter changed nothing: the test shows nothing";
}

TEST(Kernels, BackgroundAndNoDecalPixelsPassThroughBitExact) {
    RandomFrame f = makeRandomFrame(3);
    Plane& depth = f.gbuffer.planes.at(Attribute::Depth);
    depth.at(0, 0) = std::nanf("");
    depth.at(1, 0) = INFINITY;
    depth.at(2, 0) = -1.0f;
    depth.at(3, 0) = 0.0f;
    Compositor compositor(cpuDevice());
    DecalScene scene;
    scene.textures.push_back(synth::proceduralTexture(1, 8, 1));
    Decal everywhere;
    everywhere.world_matrix = glm::scale(glm::dmat4(1.0), glm::dvec3(1e4));
    everywhere.albedo_texture = 0;
    scene.decals.push_back(everywhere);
    compositor.setScene(scene);
    GBuffer out = f.gbuffer;
    compositor.composite(out, f.camera);
    const auto ref = reference::shade(f.gbuffer, f.camera, scene);
    const Plane& in = f.gbuffer.planes.at(Attribute::Albedo);
    const Plane& result = out.planes.at(Attribute::Albedo);
    std::size_t background = 0;
    for (std::size_t i = 0; i < f.gbuffer.pixelCount(); ++i) {
        if (reference::pixelWorldPoint(f.gbuffer, f.camera, int(i % f.gbuffer.width), int(i / f.gbuffer.width))) continue;
        ++background;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(std::memcmp(&in.samples[i * 3 + c], &result.samples[i * 3 + c], sizeof(float)), 0) << i;
    }
    EXPECT_GE(background, 4u);

    compositor.setScene(DecalScene{});
    GBuffer untouched = f.gbuffer;
    compositor.composite(untouched, f.camera);
    EXPECT_EQ(std::memcmp(untouched.planes.at(Attribute::Albedo).samples.data(), in.samples.data(),
                          in.samples.size() * sizeof(float)),
              0);
}

TEST(Kernels, MaskWeightsMatchReference) {
    RandomFrame f = makeRandomFrame(9);
    DecalScene decals = makeRandomDecals(f, 9, 200);
    // Two masks with smooth and hard per-pixel weights; every third decal uses one.
    decals.masks = {DecalMask{{1}, {}, "", {}}, DecalMask{{}, {2}, "", {}}};
    for (int m = 0; m < 2; ++m) {
        Plane w{1, std::vector<float>(f.gbuffer.pixelCount())};
        for (std::size_t i = 0; i < w.samples.size(); ++i)
            w.samples[i] = m == 0 ? float(i % 7) / 6.0f : float((i / 13) % 2);
        f.gbuffer.mask_weights.push_back(w);
    }
    for (std::size_t k = 0; k < decals.decals.size(); ++k) decals.decals[k].mask = k % 3 == 2 ? -1 : int(k % 3);
    const auto [out, c] = compositeAndCompare(f, decals);
    EXPECT_EQ(c.mismatched, 0u) << "max error " << c.max_error;
    // Without the masks the result must differ: the weights really reach the kernel.
    GBuffer unmasked = f.gbuffer;
    for (auto& d : decals.decals) d.mask = -1;
    decals.masks.clear();
    unmasked.mask_weights.clear();
    Compositor compositor(cpuDevice());
    compositor.setScene(decals);
    compositor.composite(unmasked, f.camera);
    EXPECT_NE(unmasked.planes.at(Attribute::Albedo).samples, out.planes.at(Attribute::Albedo).samples);
}

TEST(Kernels, DataWindowOffsetMatchesReference) {
    RandomFrame f = makeRandomFrame(6);
    // Pretend the frame is a crop of a larger display window.
    f.gbuffer.display_width = f.gbuffer.width + 30;
    f.gbuffer.display_height = f.gbuffer.height + 20;
    f.gbuffer.origin_x = 11;
    f.gbuffer.origin_y = 7;
    const DecalScene decals = makeRandomDecals(f, 6, 100);
    const auto [out, c] = compositeAndCompare(f, decals);
    EXPECT_EQ(c.mismatched, 0u) << "max error " << c.max_error;
}

}  // namespace
}  // namespace decalcomp

namespace decalcomp {
namespace {

// Without a normal pass, angle fades use normals reconstructed from depth (kernel and reference
// follow the same neighbour rule), and they do change the result.
TEST(Kernels, AngleFadeWithNormalsFromDepthMatchesReference) {
    for (std::uint32_t seed : {1u, 4u, 5u}) {
        RandomFrame f = makeRandomFrame(seed);
        f.gbuffer.planes.erase(Attribute::Normal);
        DecalScene decals = makeRandomDecals(f, seed, 150);
        for (Decal& d : decals.decals) d.angle_fade_deg = {20.0, 70.0};
        Compositor compositor(cpuDevice());
        compositor.setScene(decals);
        GBuffer out = f.gbuffer;
        compositor.composite(out, f.camera);
        const auto ref = reference::shade(f.gbuffer, f.camera, decals, roundingMargin(f.gbuffer));
        const Comparison c = compareWithReference(f.gbuffer, out, ref, albedoTolerance(f.gbuffer));
        EXPECT_EQ(c.mismatched, 0u) << "seed " << seed << " max error " << c.max_error;
        EXPECT_LT(double(c.ambiguous), 0.25 * double(f.gbuffer.pixelCount())) << "seed " << seed;

        for (Decal& d : decals.decals) d.angle_fade_deg = {0.0, 0.0};
        compositor.setScene(decals);
        GBuffer unfaded = f.gbuffer;
        compositor.composite(unfaded, f.camera);
        EXPECT_NE(unfaded.planes.at(Attribute::Albedo).samples, out.planes.at(Attribute::Albedo).samples);
    }
}

}  // namespace
}  // namespace decalcomp

namespace decalcomp {
namespace {

// A floor and a few spheres under a camera looking down at an angle, for kind-specific scenes.
RandomFrame floorFrame(std::uint32_t seed, int width, int height) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    RandomFrame f;
    f.scene.materials = {synth::Material{}};
    f.scene.planes = {{{0, 0, 0}, {0, 0, 1}, 0}};
    for (int n = 0; n < 4; ++n) f.scene.spheres.push_back({{3.0 * u(rng), 3.0 * u(rng), 0.3}, 0.6 + 0.3 * u(rng), 0});
    f.camera.world_to_camera = lookAt({u(rng), -9.0, 6.0 + u(rng)}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0});
    f.camera.projection = perspectiveProjection(glm::radians(50.0), double(width) / height, 0.1, 100.0);
    f.gbuffer = synth::render(f.scene, f.camera, synth::RenderOptions{width, height});
    return f;
}

// `count` decals of `kind` at random places over the floor frame's floor, rotated at random,
// `size(k, random in [-1, 1])` wide, alternating between the textures.
template <class Size>
DecalScene decalsOverFloor(DecalKind kind, std::vector<Texture2D> textures, int count, std::uint32_t seed, Size size) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    DecalScene scene;
    scene.textures = std::move(textures);
    for (int k = 0; k < count; ++k) {
        Decal d;
        d.kind = kind;
        glm::dmat4 m = glm::translate(glm::dmat4(1.0), {3.5 * u(rng), 3.5 * u(rng), 0.3 * u(rng)});
        m = glm::rotate(m, 3.0 * u(rng), glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + 1e-6));
        d.world_matrix = glm::scale(m, glm::dvec3(size(k, u(rng))));
        d.albedo_texture = k % int(scene.textures.size());
        scene.decals.push_back(d);
    }
    return scene;
}

// Cube decals with tiny faces (4 and 5 texels) spread over the floor and spheres, rotated at
// random, linear and mip: a large share of their pixels has a bilinear tap on a neighbour face,
// so the seamless rule (neighbour faces, corners) is compared texel for texel with the reference.
TEST(Kernels, SeamlessCubeLinearAndMipMatchReference) {
    const RandomFrame f = floorFrame(21, 150, 110);
    std::mt19937 rng(22);
    DecalScene decals = decalsOverFloor(
        DecalKind::Cube,
        {randomTexture(4, 4, 6, rng, TextureShape::Cube), randomTexture(5, 5, 6, rng, TextureShape::Cube)}, 40, 23,
        [](int, double random) { return 3.0 + 1.5 * random; });
    for (std::size_t k = 0; k < decals.decals.size(); ++k) {
        decals.decals[k].opacity = 0.8f;
        decals.decals[k].filter = k % 3 == 0 ? TextureFilter::Mip : TextureFilter::Linear;
    }
    // pixels whose lookup has a tap past a face edge (level 0)
    std::size_t seam_pixels = 0;
    for (int y = 0; y < f.gbuffer.height; ++y)
        for (int x = 0; x < f.gbuffer.width; ++x) {
            const auto p = reference::pixelWorldPoint(f.gbuffer, f.camera, x, y);
            if (!p) continue;
            for (const Decal& d : decals.decals) {
                const glm::dvec3 l(glm::inverse(d.world_matrix) * glm::dvec4(*p, 1.0));
                if (glm::length(l) > 0.5) continue;
                const reference::CubeLookup c = reference::cubeLookup(l);
                const double n = decals.textures[std::size_t(d.albedo_texture)].width;
                if (std::min(c.s, c.t) * n < 0.5 || std::max(c.s, c.t) * n > n - 0.5) {
                    ++seam_pixels;
                    break;
                }
            }
        }
    const auto [out, c] = compositeAndCompare(f, decals);
    std::printf("cube seams: %zu of %zu pixels changed, %zu with a tap on a neighbour face; max error %.2g\n",
                c.changed, f.gbuffer.pixelCount(), seam_pixels, c.max_error);
    EXPECT_EQ(c.mismatched, 0u) << "max error " << c.max_error << " over " << c.compared << " pixels";
    EXPECT_GT(double(c.changed), 0.3 * double(f.gbuffer.pixelCount()));
    EXPECT_GT(double(seam_pixels), 0.3 * double(c.changed));
    EXPECT_LT(double(c.ambiguous), 0.05 * double(f.gbuffer.pixelCount()));
}

// Volume decals with `mip` from magnified to strongly minified (small on screen, grazing): the
// quadrilinear lookup in the 3D chain (odd sizes included) matches the reference.
TEST(Kernels, VolumeMipMatchesReference) {
    const RandomFrame f = floorFrame(31, 150, 110);
    std::mt19937 rng(32);
    // from a tenth of a unit (a few pixels: the coarsest levels) to several units
    DecalScene decals = decalsOverFloor(
        DecalKind::Volume,
        {randomTexture(32, 32, 32, rng, TextureShape::Volume), randomTexture(24, 20, 9, rng, TextureShape::Volume)}, 24,
        33, [](int k, double random) { return k % 4 == 0 ? 0.1 : 2.0 + 1.5 * random; });
    for (Decal& d : decals.decals) d.filter = TextureFilter::Mip;
    const auto [out, c] = compositeAndCompare(f, decals);
    std::printf("volume mip: %zu of %zu pixels changed, max error %.2g\n", c.changed, f.gbuffer.pixelCount(),
                c.max_error);
    EXPECT_EQ(c.mismatched, 0u) << "max error " << c.max_error << " over " << c.compared << " pixels";
    EXPECT_GT(double(c.changed), 0.2 * double(f.gbuffer.pixelCount()));
    // and mip is not level 0 here: the result differs from trilinear level-0 lookups
    for (Decal& d : decals.decals) d.filter = TextureFilter::Linear;
    const auto [level0, c0] = compositeAndCompare(f, decals);
    EXPECT_NE(level0.planes.at(Attribute::Albedo).samples, out.planes.at(Attribute::Albedo).samples);
}

}  // namespace
}  // namespace decalcomp

namespace decalcomp {
namespace {

// setDecals (animated batches) keeps the uploaded textures: the same decals give the same bits as
// a full setScene, and indices beyond the uploaded textures are refused.
TEST(Kernels, SetDecalsMatchesSetScene) {
    const test::RandomFrame f = test::makeRandomFrame(7);
    const DecalScene scene = test::makeRandomDecals(f, 7, 120);
    Compositor full(test::cpuDevice()), swapped(test::cpuDevice());
    full.setScene(scene);
    DecalScene first_half = scene;
    first_half.decals.resize(scene.decals.size() / 2);
    swapped.setScene(first_half);
    swapped.setDecals(scene.decals);
    GBuffer a = f.gbuffer, b = f.gbuffer;
    full.composite(a, f.camera);
    swapped.composite(b, f.camera);
    EXPECT_EQ(a.planes.at(Attribute::Albedo).samples, b.planes.at(Attribute::Albedo).samples);
    EXPECT_NE(a.planes.at(Attribute::Albedo).samples, f.gbuffer.planes.at(Attribute::Albedo).samples);
    Decal stray = scene.decals.front();
    stray.albedo_texture = int(scene.textures.size());
    EXPECT_THROW(swapped.setDecals({stray}), Error);
}

}  // namespace
}  // namespace decalcomp
