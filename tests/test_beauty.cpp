// The beauty follows the decals (issue 14): Blender's Combined rebuilt from its light passes against
// Cycles' own render of the decals, the analytic generator's passes (exact), the kernel against the
// scalar reference on PoCL's CPU device (divided and multiplied light), and the CLI's control.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "decalcomp/compositor.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/reference.hpp"
#include "decalcomp/synth.hpp"
#include "decalcomp/synth_antialias.hpp"
#include "decalcomp/synth_light.hpp"
#include "support/exr_test_io.hpp"
#include "support/random_scenes.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::floatSamples;

// PSNR (peak 1) of Combined R,G,B against the truth over the truth's DecalMask > 0.5.
double beautyPsnr(const ExrImage& result, const ExrImage& truth) {
    const std::vector<float> mask = floatSamples(truth, "ViewLayer.DecalMask.X");
    double squared = 0;
    std::size_t samples = 0;
    for (const char* c : {"R", "G", "B"}) {
        const std::string name = std::string("ViewLayer.Combined.") + c;
        const std::vector<float> a = floatSamples(result, name), b = floatSamples(truth, name);
        for (std::size_t i = 0; i < mask.size(); ++i)
            if (mask[i] > 0.5f) squared += double(a[i] - b[i]) * double(a[i] - b[i]), ++samples;
    }
    return 10.0 * std::log10(double(samples) / std::max(squared, 1e-30));
}

test::CommandResult compositeBeauty(const std::string& folder, const std::string& out, const std::string& extra = "") {
    return test::runCli("composite " + test::shellQuote(test::dataPath(folder + "/gbuffer.exr")) + " --decals " +
                        test::shellQuote(test::dataPath("blender-kinds/scene.json")) + " --camera " +
                        test::shellQuote(test::dataPath(folder + "/camera.json")) + " --device cpu -o " +
                        test::shellQuote(out) + " " + extra);
}

// Composites a beauty dataset and scores the rebuilt and the untouched Combined against Cycles'.
void expectRebuiltAbove(const std::string& folder, double floor) {
    test::ScratchDir dir;
    const auto run = compositeBeauty(folder, dir.file("out.exr"));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("beauty: rebuilt ViewLayer.Combined.{R,G,B} from ViewLayer.DiffDir.{R,G,B} + "
                              "ViewLayer.DiffInd.{R,G,B}"),
              std::string::npos)
        << run.output;
    const ExrImage truth = readExr(test::dataPath(folder + "/truth.exr"));
    const double rebuilt = beautyPsnr(readExr(dir.file("out.exr")), truth);
    const double untouched = beautyPsnr(readExr(test::dataPath(folder + "/gbuffer.exr")), truth);
    ::testing::Test::RecordProperty("psnr_db", std::to_string(rebuilt));
    ::testing::Test::RecordProperty("untouched_psnr_db", std::to_string(untouched));
    EXPECT_GE(rebuilt, floor);
    EXPECT_LT(untouched, 20.0);
}

// The README's numpy figures (shared data/README.md, "Beauty datasets"), given to 0.1 dB: 51.7 dB
// with direct light only, 35.2 dB with bounces (which the passes cannot follow); untouched about
// 16 dB. Measured here on PoCL: 51.66 and 35.20 dB (untouched 16.77 and 15.73): the floors sit
// just below.
TEST(BeautyTruth, DirectLightReachesTheNumpyFigure) { expectRebuiltAbove("blender-beauty-direct", 51.6); }
TEST(BeautyTruth, BouncedLightReachesTheNumpyFigure) { expectRebuiltAbove("blender-beauty", 35.15); }

// Alpha, the (divided) light passes and the background keep their bits; the beauty changes only
// where the albedo did.
TEST(BeautyTruth, AlphaLightAndBackgroundStayBitExact) {
    test::ScratchDir dir;
    ASSERT_EQ(compositeBeauty("blender-beauty-direct", dir.file("out.exr"), "-q").exit_code, 0);
    const ExrImage in = readExr(test::dataPath("blender-beauty-direct/gbuffer.exr"));
    const ExrImage out = readExr(dir.file("out.exr"));
    for (const char* name : {"ViewLayer.Combined.A", "ViewLayer.DiffDir.R", "ViewLayer.DiffInd.B", "ViewLayer.Depth.Z"})
        EXPECT_EQ(test::channel(in, name).bytes, test::channel(out, name).bytes) << name;
    const std::vector<float> depth = floatSamples(in, "ViewLayer.Depth.Z");
    std::size_t changed = 0;
    for (const char* c : {"R", "G", "B"}) {
        const std::vector<float> b0 = floatSamples(in, std::string("ViewLayer.Combined.") + c);
        const std::vector<float> b1 = floatSamples(out, std::string("ViewLayer.Combined.") + c);
        const std::vector<float> a0 = floatSamples(in, std::string("ViewLayer.DiffCol.") + c);
        const std::vector<float> a1 = floatSamples(out, std::string("ViewLayer.DiffCol.") + c);
        for (std::size_t i = 0; i < depth.size(); ++i) {
            const bool same_beauty = std::memcmp(&b0[i], &b1[i], 4) == 0;
            if (depth[i] >= 1e10f) {
                EXPECT_TRUE(same_beauty) << "background pixel " << i;
            }
            if (std::memcmp(&a0[i], &a1[i], 4) == 0) {
                EXPECT_TRUE(same_beauty) << "pixel " << i << " albedo unchanged";
            }
            changed += !same_beauty;
        }
    }
    EXPECT_GT(changed, 10000u);
}

// Edge pixels (a depth step to a neighbour): the update changes them as the albedo says; over
// them, the rebuilt beauty is nearer the truth than the untouched one.
TEST(BeautyTruth, EdgePixelsGetNoWorseThanUntouched) {
    test::ScratchDir dir;
    ASSERT_EQ(compositeBeauty("blender-beauty-direct", dir.file("out.exr"), "-q").exit_code, 0);
    const ExrImage in = readExr(test::dataPath("blender-beauty-direct/gbuffer.exr"));
    const ExrImage out = readExr(dir.file("out.exr"));
    const ExrImage truth = readExr(test::dataPath("blender-beauty-direct/truth.exr"));
    const std::vector<float> depth = floatSamples(in, "ViewLayer.Depth.Z"),
                             mask = floatSamples(truth, "ViewLayer.DecalMask.X");
    const int w = in.parts[0].width, h = in.parts[0].height;
    double rebuilt = 0, untouched = 0;
    std::size_t edges = 0;
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (depth[i] >= 1e10f || !(mask[i] > 0.0f)) continue;
            bool edge = false;
            for (std::size_t j : {i - 1, i + 1, i - std::size_t(w), i + std::size_t(w)})
                edge = edge || std::abs(depth[j] - depth[i]) > 0.05f * depth[i];
            if (!edge) continue;
            ++edges;
            for (const char* c : {"R", "G", "B"}) {
                const std::string name = std::string("ViewLayer.Combined.") + c;
                const double t = floatSamples(truth, name)[i];
                rebuilt += std::pow(floatSamples(out, name)[i] - t, 2);
                untouched += std::pow(floatSamples(in, name)[i] - t, 2);
            }
        }
    RecordProperty("edge_pixels", std::to_string(edges));
    EXPECT_GT(edges, 10u);
    EXPECT_LT(rebuilt, untouched) << edges << " edge pixels";
}

// The generator's beauty (RGB) and its two light terms, direct and indirect, divided as Blender's.
BeautyPlanes generatorPlanes(const synth::LightPasses& light, std::size_t pixels) {
    BeautyPlanes planes;
    planes.beauty = {3, {}};
    for (std::size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) planes.beauty.samples.push_back(light.beauty.at(i, c));
    planes.light = {light.direct, light.indirect};
    planes.direct_terms = 1;
    planes.summed_terms = 2;
    return planes;
}

// Checks that the beauty is albedo * (DiffDir + DiffInd) at every pixel to float rounding, and
// returns how many albedo samples differ from `before`.
std::size_t expectExactBeauty(const GBuffer& frame, const GBuffer& before, const synth::LightPasses& light,
                              const BeautyPlanes& planes) {
    const Plane& albedo = frame.planes.at(Attribute::Albedo);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < frame.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double exact = double(albedo.at(i, c)) * (double(light.direct.at(i, c)) + light.indirect.at(i, c));
            EXPECT_NEAR(planes.beauty.at(i, c), exact, 4e-7 * std::max(1.0, std::abs(exact))) << "pixel " << i;
            if (std::abs(planes.beauty.at(i, c) - exact) > 4e-7 * std::max(1.0, std::abs(exact))) return changed;
            changed += albedo.at(i, c) != before.planes.at(Attribute::Albedo).at(i, c);
        }
    return changed;
}

// The generator's Combined is exactly albedo * (DiffDir + DiffInd): the update is exact to float
// rounding, binned (the host adds the changes of the listed tiles only) and unbinned.
class BeautyAnalytic : public ::testing::TestWithParam<bool> {};
INSTANTIATE_TEST_SUITE_P(Binning, BeautyAnalytic, ::testing::Bool(),
                         [](const auto& binning) { return binning.param ? "binned" : "unbinned"; });

TEST_P(BeautyAnalytic, GeneratorPassesRebuildExactly) {
    const Camera camera = synth::demoCamera(160, 120);
    GBuffer frame = synth::render(synth::demoScene(), camera, {160, 120});
    const DecalScene scene = synth::scatterDecals(frame, camera, {24, 0.4, 1.2});
    const synth::LightPasses light = synth::lightPasses(frame);
    BeautyPlanes planes = generatorPlanes(light, frame.pixelCount());
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    const GBuffer before = frame;
    compositor.composite(frame, camera, {GetParam()}, &planes);
    EXPECT_GT(expectExactBeauty(frame, before, light, planes), 1000u);
}

// A compositor reused for a frame whose decals reach other tiles: the changes the kernel left in its
// device memory for the first frame must not reach the second frame's beauty.
TEST_P(BeautyAnalytic, ReusedCompositorAddsOnlyThisFramesChanges) {
    const Camera camera = synth::demoCamera(160, 120);
    const GBuffer frame = synth::render(synth::demoScene(), camera, {160, 120});
    const synth::LightPasses light = synth::lightPasses(frame);
    Compositor compositor(test::cpuDevice());
    // first frame: decals everywhere
    GBuffer first = frame;
    BeautyPlanes first_planes = generatorPlanes(light, frame.pixelCount());
    compositor.setScene(synth::scatterDecals(frame, camera, {48, 0.4, 1.2}));
    compositor.composite(first, camera, {GetParam()}, &first_planes);
    // second frame: two small decals centred on the top rows only
    synth::ScatterOptions few{2, 0.2, 0.3};
    few.seed = 7;
    few.last_row = 20;
    compositor.setScene(synth::scatterDecals(frame, camera, few));
    GBuffer second = frame;
    BeautyPlanes planes = generatorPlanes(light, frame.pixelCount());
    compositor.composite(second, camera, {GetParam()}, &planes);
    const std::size_t changed = expectExactBeauty(second, frame, light, planes);  // albedo samples
    EXPECT_GT(changed, 0u);
    EXPECT_LT(changed, 3 * frame.pixelCount() / 4) << "the second frame's decals reach under a quarter of it";
}

// The kernel against the scalar reference, light divided (Blender) and multiplied (Arnold):
// same beauty and rewritten light terms.
class BeautyKernel : public ::testing::TestWithParam<bool> {};

TEST_P(BeautyKernel, MatchesTheReference) {
    const bool divided = GetParam();
    const Camera camera = synth::demoCamera(128, 96);
    GBuffer frame = synth::render(synth::demoScene(), camera, {128, 96});
    const DecalScene scene = synth::scatterDecals(frame, camera, {32, 0.3, 1.0, 4, 32, 7});
    const synth::LightPasses light = synth::lightPasses(frame);
    BeautyPlanes planes;
    planes.divided = divided;
    planes.beauty = {3, {}};
    for (std::size_t i = 0; i < frame.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) planes.beauty.samples.push_back(light.beauty.at(i, c) + 0.01f);
    planes.light = {light.direct, light.indirect, light.direct};  // the last: a "total" term, not summed
    planes.direct_terms = 1;
    planes.summed_terms = 2;
    if (!divided)  // multiplied: light * albedo
        for (Plane& term : planes.light)
            for (std::size_t i = 0; i < frame.pixelCount(); ++i)
                for (int c = 0; c < 3; ++c) term.at(i, c) *= frame.planes.at(Attribute::Albedo).at(i, c);
    BeautyPlanes expected = planes;
    const GBuffer before = frame;
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    compositor.composite(frame, camera, {}, &planes);
    reference::updateBeauty(before.planes, frame.planes, expected);
    for (std::size_t k = 0; k < expected.beauty.samples.size(); ++k)
        ASSERT_NEAR(planes.beauty.samples[k], expected.beauty.samples[k], 2e-6) << "sample " << k;
    for (std::size_t t = 0; t < planes.light.size(); ++t)
        for (std::size_t k = 0; k < expected.light[t].samples.size(); ++k)
            ASSERT_NEAR(planes.light[t].samples[k], expected.light[t].samples[k], 2e-6)
                << "term " << t << " sample " << k;
}

INSTANTIATE_TEST_SUITE_P(Light, BeautyKernel, ::testing::Values(true, false),
                         [](const auto& param) { return param.param ? "Divided" : "Multiplied"; });

// Mixed pixels of a filtered frame (silhouettes, creases): divided light takes the least light of
// each term around the pixel, kernel and reference alike (docs/profiles.md "Mixed pixels"). The demo
// scene rendered 4x finer and filtered down with Blackman-Harris 3 px, as Cycles filters.
TEST(BeautyKernel, MixedPixelsTakeTheLeastLight) {
    constexpr int kWidth = 128, kHeight = 96, kFactor = 4;
    const Camera fine_camera = synth::demoCamera(kWidth * kFactor, kHeight * kFactor);
    const GBuffer fine =
        synth::render(synth::demoScene(), fine_camera, synth::RenderOptions{kWidth * kFactor, kHeight * kFactor});
    const Camera camera = synth::demoCamera(kWidth, kHeight);
    GBuffer frame = synth::filterDown(fine, kFactor, parsePixelFilter("blackman-harris:3", ""));
    const DecalScene scene = synth::scatterDecals(frame, camera, {48, 0.4, 1.2, 4, 16, 3});
    const synth::LightPasses light = synth::lightPasses(frame);
    BeautyPlanes planes = generatorPlanes(light, frame.pixelCount());
    BeautyPlanes expected = planes, plain = planes;
    const GBuffer before = frame;
    Compositor compositor(test::cpuDevice());
    compositor.setScene(scene);
    compositor.composite(frame, camera, {}, &planes);
    const reference::MixedPixels mixed = reference::mixedPixels(before, camera);
    reference::updateBeauty(before.planes, frame.planes, expected, mixed);
    reference::updateBeauty(before.planes, frame.planes, plain);
    std::size_t mixed_changed = 0, least_differs = 0;
    for (std::size_t i = 0; i < frame.pixelCount(); ++i) {
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(planes.beauty.at(i, c), expected.beauty.at(i, c), 2e-6) << "pixel " << i << " channel " << c;
        if (mixed.surfaces[i] == 0) continue;
        bool changed = false, differs = false;
        for (int c = 0; c < 3; ++c) {
            changed |= frame.planes.at(Attribute::Albedo).at(i, c) != before.planes.at(Attribute::Albedo).at(i, c);
            differs |= std::abs(expected.beauty.at(i, c) - plain.beauty.at(i, c)) > 1e-3;
        }
        mixed_changed += changed;
        least_differs += differs;
    }
    // decals reach many silhouettes, and there the least light differs from the pixel's own
    EXPECT_GT(mixed_changed, 100u);
    EXPECT_GT(least_differs, 20u);
}

// No light passes: auto warns that the beauty is not rebuilt, on fails naming them, off is silent.
TEST(BeautyControl, MissingPassesWarnOrFail) {
    test::ScratchDir dir;
    const auto run = [&](const std::string& mode) {
        return test::runCli("composite " + test::shellQuote(test::dataPath("blender-kinds/gbuffer.exr")) +
                            " --decals " + test::shellQuote(test::dataPath("blender-kinds/scene.json")) + " --camera " +
                            test::shellQuote(test::dataPath("blender-kinds/camera.json")) + " --device cpu -q -o " +
                            test::shellQuote(dir.file("out.exr")) + " --beauty " + mode);
    };
    const auto automatic = run("auto");
    EXPECT_EQ(automatic.exit_code, 0) << automatic.output;
    EXPECT_NE(automatic.output.find("is not rebuilt: light passes missing: diffuse direct (ViewLayer.DiffDir.{R,G,B})"),
              std::string::npos)
        << automatic.output;
    const auto on = run("on");
    EXPECT_EQ(on.exit_code, 3) << on.output;
    EXPECT_NE(on.output.find("--beauty on: light passes missing: diffuse direct (ViewLayer.DiffDir.{R,G,B})"),
              std::string::npos)
        << on.output;
    const auto off = run("off");
    EXPECT_EQ(off.exit_code, 0);
    EXPECT_EQ(off.output.find("beauty"), std::string::npos) << off.output;
}

TEST(BeautyControl, InfoShowsTheModelAndPasses) {
    const auto run = test::runCli("info " + test::shellQuote(test::dataPath("blender-beauty/gbuffer.exr")));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    for (const char* needle :
         {"beauty:", "model: blender (divided light", "beauty: ViewLayer.Combined.{R,G,B}",
          "albedo lobe: direct ViewLayer.DiffDir.{R,G,B}, indirect ViewLayer.DiffInd.{R,G,B}", "rebuild: yes"})
        EXPECT_NE(run.output.find(needle), std::string::npos) << needle << "\n" << run.output;
}

// The preview gains a third row: the beauty before | after.
TEST(BeautyControl, PreviewShowsTheBeautyRow) {
    test::ScratchDir dir;
    ASSERT_EQ(
        compositeBeauty("blender-beauty-direct", dir.file("out.exr"), "-q --preview " + dir.file("p.png")).exit_code,
        0);
    const test::Png png = test::readPng(dir.file("p.png"));
    EXPECT_EQ(png.width, 2 * 320 + 4);
    EXPECT_EQ(png.height, 3 * 240 + 2 * 4);
}

}  // namespace
}  // namespace decalcomp
