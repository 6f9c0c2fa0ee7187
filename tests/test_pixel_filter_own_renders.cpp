// Issue 15 on antialiased Blender renders of our own (data/blender-aa-gauss: Cycles' Gaussian,
// Filter Size 2.5 px; data/blender-aa-box: Cycles' Box, 1 px), made from scratch by
// tools/blender/make_datasets.sh (data/README.md "Our own renders"). The issue's target: "on other
// antialiased Blender scenes of this kind, the same method must land within 5 dB of the
// 4x-supersampled estimate" (decals composited at 4x without antialiasing and filtered down with the
// renderer's filter; tools/blender/estimate_4x.py, independent numpy, recorded in estimate.json).
// With silhouette and crease pixels split between their two surfaces (docs/pixel-filter.md
// "Silhouettes", "Creases") and decals stacked per tap (step 3) both renders meet it: box 45.92 dB
// against a bar of 37.95, Gaussian 45.05 against 43.61. These tests assert the bar, hold decalcomp to
// what it measures today so that no loss goes unseen, and check that filtering beats point sampling
// everywhere, on mixed pixels too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "decalcomp/exr_file.hpp"
#include "support/test_support.hpp"
#include "support/truth_score.hpp"

namespace decalcomp {
namespace {

using test::compareMixedPixels;
using test::findFloatChannel;
using test::MixedPixels;
using test::Score;
using test::scoreAgainstTruth;

struct OwnRender {
    const char* folder;
    const char* filter;      // --pixel-filter matching the render (measured by estimate_4x.py's fit)
    double estimate_db;      // the 4x estimate with that filter (estimate.json "estimate_db")
    double mixed_noise;      // per-pixel noise bound of the truth's DiffCol (see below)
    double measured_db;      // decalcomp's score with split silhouettes (PoCL; deterministic)
    std::size_t measured_worse;  // mixed pixels worse than point-sampled beyond the noise, the same
};

// Measured (data/README.md "Our own renders", tools/blender/estimate_4x.py):
// - gauss: Cycles' Gaussian 2.5 px is gaussian:2.5 here (the fit over gaussian:1.0..4.0 in steps of
//   0.1 peaks at 2.5: 48.61 dB over the decal pixels; 2.4 and 2.6 score lower). The 4x estimate with
//   it: 48.61 dB.
// - box: Cycles' Box 1 px is box:1 (the fit over box:0.5/1/1.5/2 peaks at 1: 42.95 dB; the 4x grid
//   has only 4 x 4 samples per pixel, which caps the estimate). The 4x estimate: 42.95 dB.
// - mixed_noise: the largest per-pixel channel difference of DiffCol between the truth and the same
//   render with seed 1 instead of 0 (own_scene.py --seed 1, otherwise the same command), over the
//   truth's decal pixels: two equally valid 256-spp renders differ this much (gauss 0.0370, box
//   0.0261; over the mixed decal pixels alone 0.0259 and 0.0192; seed 0 against seed 1 scores
//   50.33 and 55.09 dB over the decal pixels).
// Before silhouettes were split (a3c5671): gauss 35.17 dB with 14 pixels worse, box 37.88 with 10;
// before decals were stacked per tap (2211c2f): gauss 40.37 dB, box 42.29; before creases were split
// (381a4de): gauss 42.75 with 9 pixels worse, box 43.32 with 12; before silhouette splits had to
// explain the pixel's normal (3808a85): gauss 44.99 with 3, box 44.01 with 9.
const OwnRender kGauss{"blender-aa-gauss", "gaussian:2.5", 48.61, 0.0370, 45.05, 2};
const OwnRender kBox{"blender-aa-box", "box:1", 42.95, 0.0261, 45.92, 6};
// The closed form (`:fast`, docs/pixel-filter.md "Integrated evaluation") on the same renders:
// gauss 40.31 dB (2 mixed pixels worse), box 43.02 (6). It blends one decal at a time, and these
// scenes pile decals on each other: the taps one decal at a time score 41.59 and 44.24 (kernel
// variant, 2026-12-05), against 45.05 and 45.92 stacked per tap. So the Gaussian's fast result
// misses issue 15's bar (43.61) while the box's meets it (37.95).
const OwnRender kGaussFast{"blender-aa-gauss", "gaussian:2.5:fast", 48.61, 0.0370, 40.31, 2};
const OwnRender kBoxFast{"blender-aa-box", "box:1:fast", 42.95, 0.0261, 43.02, 6};

void compositeOwn(const std::string& folder, const std::string& filter, const std::string& out) {
    const auto file = [&](const std::string& f) { return test::shellQuote(test::dataPath(folder + "/" + f)); };
    const auto run = test::runCli("composite " + file("gbuffer.exr") + " --decals " + file("scene.json") +
                                  " --camera " + file("camera.json") + " --device cpu -q --beauty off --pixel-filter " +
                                  filter + " -o " + test::shellQuote(out));
    EXPECT_EQ(run.exit_code, 0) << run.output;
}

struct Measured {
    Score all, point;
    MixedPixels mixed;
};

// Composites one render with its filter and point-sampled, scores both (once per render; the tests
// below share it).
const Measured& measure(const OwnRender& render) {
    static std::map<std::string, Measured> cache;
    const std::string key = std::string(render.folder) + " " + render.filter;
    const auto found = cache.find(key);
    if (found != cache.end()) return found->second;
    test::ScratchDir dir;
    Measured m;
    compositeOwn(render.folder, render.filter, dir.file("filtered.exr"));
    compositeOwn(render.folder, "none", dir.file("point.exr"));
    const ExrImage truth = readExr(test::dataPath(std::string(render.folder) + "/truth.exr"));
    const ExrImage filtered = readExr(dir.file("filtered.exr"));
    const ExrImage point = readExr(dir.file("point.exr"));
    m.all = scoreAgainstTruth(filtered, truth);
    m.point = scoreAgainstTruth(point, truth);
    std::printf("%s, --pixel-filter %s: %.2f dB over %zu decal pixels (4x estimate %.2f, point-sampled %.2f)\n",
                render.folder, render.filter, m.all.psnr, m.all.pixels / 3, render.estimate_db, m.point.psnr);
    for (const char* kind : {"Box", "Frustum"}) {
        const Score score = scoreAgainstTruth(filtered, truth, std::string("ViewLayer.DecalMask") + kind + ".X");
        std::printf("  %s: %.2f dB over %zu pixels\n", kind, score.psnr, score.pixels / 3);
    }
    m.mixed = compareMixedPixels(test::dataPath(std::string(render.folder) + "/gbuffer.exr"), filtered, point, truth,
                                 render.mixed_noise);
    std::printf("  mixed pixels: %zu, worse than point-sampled by > %.4f (the truth's noise): %zu (worst by %.4f at "
                "x %d, y %d); filtered %.2f dB, point %.2f dB\n",
                m.mixed.pixels, render.mixed_noise, m.mixed.worse, m.mixed.worst_excess, m.mixed.worst_x,
                m.mixed.worst_y, m.mixed.filtered_psnr, m.mixed.point_psnr);
    return cache.emplace(key, m).first->second;
}

// The score over the decal pixels stays where it was measured (0.5 dB of slack for other compilers'
// rounding); the bar, the estimate less 5 dB, is printed beside it.
void expectMeasuredLevel(const OwnRender& render) {
    const Measured& m = measure(render);
    ::testing::Test::RecordProperty("psnr_db", std::to_string(m.all.psnr));
    // 16,487 (gauss) and 16,488 (box) decal pixels (estimate.json "decal_pixels")
    EXPECT_GT(m.all.pixels / 3, 16000u);
    std::printf("  issue 15's bar (4x estimate - 5 dB): %.2f dB; decalcomp %.2f dB\n", render.estimate_db - 5.0,
                m.all.psnr);
    EXPECT_GE(m.all.psnr, render.measured_db - 0.5);
}

// Integrating over the filter beats point sampling, over all decal pixels and over the mixed ones.
// Point sampling misses every soft edge: measured 21.66 (gauss) and 24.35 dB (box), 13.5 dB below the
// filtered result in both; "clearly lower" is 10 dB here. Mixed pixels: measured 1821 and 842, filtered
// 33.52 / 30.72 dB (26.26 / 25.41 before silhouettes were split) against point-sampled 21.27 / 22.44.
void expectBeatsPointSampling(const OwnRender& render) {
    const Measured& m = measure(render);
    ::testing::Test::RecordProperty("point_psnr_db", std::to_string(m.point.psnr));
    EXPECT_LT(m.point.psnr, m.all.psnr - 10.0);
    EXPECT_GT(m.mixed.pixels, 500u);
    EXPECT_GT(m.mixed.filtered_psnr, m.mixed.point_psnr);
}

// Mixed pixels worse than point-sampled by more than the truth's own noise: a few creases (the cube's
// edge between its top and front faces under the glyph decal, x 115, y 96, whose averaged plane lies
// between the faces) and silhouettes where a third surface shows between the two that the split
// takes (box: x 78, y 157, a face seen edge-on between them, worse by 0.40). Their count may not grow.
void expectFewMixedPixelsWorse(const OwnRender& render) {
    const Measured& m = measure(render);
    ::testing::Test::RecordProperty("mixed_worse", std::to_string(m.mixed.worse));
    ::testing::Test::RecordProperty("mixed_worst_excess", std::to_string(m.mixed.worst_excess));
    EXPECT_LE(m.mixed.worse, render.measured_worse) << "worst by " << m.mixed.worst_excess << " at x "
                                                    << m.mixed.worst_x << ", y " << m.mixed.worst_y;
}

TEST(OwnAntialiasedRenders, GaussianKeepsItsMeasuredScore) { expectMeasuredLevel(kGauss); }
TEST(OwnAntialiasedRenders, BoxKeepsItsMeasuredScore) { expectMeasuredLevel(kBox); }

// Issue 15's bar: within 5 dB of the 4x-supersampled estimate.
TEST(OwnAntialiasedRenders, BoxWithinFiveDecibelsOfTheEstimate) {
    EXPECT_GE(measure(kBox).all.psnr, kBox.estimate_db - 5.0);
}
TEST(OwnAntialiasedRenders, GaussianWithinFiveDecibelsOfTheEstimate) {
    EXPECT_GE(measure(kGauss).all.psnr, kGauss.estimate_db - 5.0);
}
TEST(OwnAntialiasedRenders, GaussianBeatsPointSampling) { expectBeatsPointSampling(kGauss); }
TEST(OwnAntialiasedRenders, BoxBeatsPointSampling) { expectBeatsPointSampling(kBox); }
TEST(OwnAntialiasedRenders, GaussianFewMixedPixelsWorseThanPointSampled) { expectFewMixedPixelsWorse(kGauss); }
TEST(OwnAntialiasedRenders, BoxFewMixedPixelsWorseThanPointSampled) { expectFewMixedPixelsWorse(kBox); }

TEST(OwnAntialiasedRenders, GaussianFastKeepsItsMeasuredScore) { expectMeasuredLevel(kGaussFast); }
TEST(OwnAntialiasedRenders, BoxFastKeepsItsMeasuredScore) { expectMeasuredLevel(kBoxFast); }
TEST(OwnAntialiasedRenders, BoxFastWithinFiveDecibelsOfTheEstimate) {
    EXPECT_GE(measure(kBoxFast).all.psnr, kBoxFast.estimate_db - 5.0);
}
TEST(OwnAntialiasedRenders, GaussianFastBeatsPointSampling) { expectBeatsPointSampling(kGaussFast); }
TEST(OwnAntialiasedRenders, BoxFastBeatsPointSampling) { expectBeatsPointSampling(kBoxFast); }
TEST(OwnAntialiasedRenders, GaussianFastFewMixedPixelsWorseThanPointSampled) { expectFewMixedPixelsWorse(kGaussFast); }
TEST(OwnAntialiasedRenders, BoxFastFewMixedPixelsWorseThanPointSampled) { expectFewMixedPixelsWorse(kBoxFast); }

}  // namespace
}  // namespace decalcomp
