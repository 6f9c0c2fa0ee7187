// Issue 14 on an antialiased render of our own: "Test it on a render of your own with Blender's
// default 1.5 px filter (Blackman-Harris): no pixel may get worse than leaving it untouched would."
// data/blender-beauty-aa (tools/blender/make_datasets.sh, data/README.md "Our own renders"): Blender's
// default pixel filter, 128 spp, direct light only, light passes; gbuffer.exr without the decals,
// truth.exr with them, both with seed 0 (so pixels no decal reaches are bit-identical in both).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/exr_file.hpp"
#include "support/exr_test_io.hpp"
#include "support/test_support.hpp"
#include "support/truth_score.hpp"

namespace decalcomp {
namespace {

using test::floatSamples;

const std::string kFolder = "blender-beauty-aa";

// The largest per-pixel difference two equally valid renders of the decals show in Combined: the
// truth rendered again with seed 1 instead of 0 (tools/blender/own_scene.py --seed 1, same command
// otherwise), max over the truth's decal pixels of the largest channel difference: 0.0325 (seed 0
// against seed 1: 50.33 dB over the decal pixels; data/README.md). A rebuilt pixel within this of
// the untouched one's error is not "worse" beyond the truth's noise. (It bounds the rebuild's noise
// from above: gbuffer and truth share seed 0, and only where the albedo differs do Cycles' lobe
// choices, and so the noise, part.)
constexpr double kNoise = 0.0325;

struct Planes {
    std::vector<float> c[3], a[3];  // Combined, DiffCol
};

Planes planes(const ExrImage& image) {
    Planes p;
    const char* rgb[3] = {"R", "G", "B"};
    for (int k = 0; k < 3; ++k) {
        p.c[k] = floatSamples(image, std::string("ViewLayer.Combined.") + rgb[k]);
        p.a[k] = floatSamples(image, std::string("ViewLayer.DiffCol.") + rgb[k]);
    }
    return p;
}

double psnrOver(const std::vector<float> (&x)[3], const std::vector<float> (&y)[3], const std::vector<float>& mask) {
    double squared = 0;
    std::size_t n = 0;
    for (int k = 0; k < 3; ++k)
        for (std::size_t i = 0; i < mask.size(); ++i)
            if (mask[i] > 0.5f) squared += double(x[k][i] - y[k][i]) * double(x[k][i] - y[k][i]), ++n;
    return 10.0 * std::log10(double(n) / std::max(squared, 1e-30));
}

double maxError(const std::vector<float> (&x)[3], const std::vector<float> (&y)[3], std::size_t i) {
    double e = 0;
    for (int k = 0; k < 3; ++k) e = std::max(e, double(std::abs(x[k][i] - y[k][i])));
    return e;
}

struct Measured {
    double rebuilt_db = 0, untouched_db = 0, albedo_db = 0;
    std::size_t worse = 0, worse_mixed = 0, worse_albedo = 0, worse_formula = 0;
    double worst = 0;
    int worst_x = -1, worst_y = -1;
};

// Composites the dataset with --beauty on and the default filter once, and measures it (the tests
// below share it).
const Measured& measure() {
    static std::optional<Measured> cached;
    if (cached) return *cached;
    Measured result;
    test::ScratchDir dir;
    const auto file = [](const std::string& f) { return test::shellQuote(test::dataPath(kFolder + "/" + f)); };
    const auto run = test::runCli("composite " + file("gbuffer.exr") + " --decals " + file("scene.json") +
                                  " --camera " + file("camera.json") + " --device cpu --beauty on -o " +
                                  test::shellQuote(dir.file("out.exr")));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    // the default (auto) filter: the frame's normals are averaged at edges, so the profile's
    EXPECT_NE(run.output.find("pixel filter: blackman-harris:3 (profile blender)"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("beauty: rebuilt ViewLayer.Combined.{R,G,B}"), std::string::npos) << run.output;

    const ExrImage in = readExr(test::dataPath(kFolder + "/gbuffer.exr"));
    const ExrImage truth_image = readExr(test::dataPath(kFolder + "/truth.exr"));
    const Planes before = planes(in), after = planes(readExr(dir.file("out.exr"))), truth = planes(truth_image);
    const std::vector<float> mask = floatSamples(truth_image, "ViewLayer.DecalMask.X");
    const test::MixedPixelTest mixed(in);
    std::vector<float> light[3];
    const char* rgb[3] = {"R", "G", "B"};
    for (int k = 0; k < 3; ++k) {
        light[k] = floatSamples(in, std::string("ViewLayer.DiffDir.") + rgb[k]);
        const std::vector<float> indirect = floatSamples(in, std::string("ViewLayer.DiffInd.") + rgb[k]);
        for (std::size_t i = 0; i < light[k].size(); ++i) light[k][i] += indirect[i];
    }
    const int width = in.parts.at(0).width;

    result.rebuilt_db = psnrOver(after.c, truth.c, mask);
    result.untouched_db = psnrOver(before.c, truth.c, mask);
    result.albedo_db = psnrOver(after.a, truth.a, mask);
    std::printf("beauty over the decal pixels: rebuilt %.2f dB, untouched %.2f dB; albedo %.2f dB\n",
                result.rebuilt_db, result.untouched_db, result.albedo_db);

    // Per pixel, over the whole frame: the rebuilt Combined may not be further from the truth than
    // the untouched one by more than the truth's noise. For the pixels that are, the diagnosis:
    // mixed (normal shorter than 0.995 or a depth jump of 2 % to a 4-neighbour), albedo off (decalcomp's
    // DiffCol more than 0.01 from the truth's), and whether the formula itself fails there: fed with
    // the truth's own DiffCol, Combined + (DiffDir + DiffInd) (A_truth - A) is also worse than untouched.
    std::size_t& worse = result.worse;
    double& worst = result.worst;
    std::size_t worst_i = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        const double rebuilt = maxError(after.c, truth.c, i), untouched = maxError(before.c, truth.c, i);
        if (rebuilt - untouched > worst) worst = rebuilt - untouched, worst_i = i;
        if (!(rebuilt > untouched + kNoise)) continue;
        ++worse;
        result.worse_mixed += mixed(i);
        result.worse_albedo += maxError(after.a, truth.a, i) > 0.01;
        double formula = 0;
        for (int k = 0; k < 3; ++k) {
            const double c = before.c[k][i] + double(light[k][i]) * (truth.a[k][i] - before.a[k][i]);
            formula = std::max(formula, std::abs(c - truth.c[k][i]));
        }
        result.worse_formula += formula > untouched + kNoise;
    }
    result.worst_x = int(worst_i % std::size_t(width));
    result.worst_y = int(worst_i / std::size_t(width));
    std::printf("pixels worse than untouched by more than %.4f: %zu (mixed %zu, albedo off by > 0.01 %zu, worse "
                "even with the truth's albedo %zu); worst by %.4f at x %d, y %d\n",
                kNoise, result.worse, result.worse_mixed, result.worse_albedo, result.worse_formula, result.worst,
                result.worst_x, result.worst_y);
    cached = result;
    return *cached;
}

// Over the decal pixels the rebuilt beauty is far nearer the truth than the untouched one. Measured
// 36.84 dB rebuilt, 18.88 untouched (18 dB apart; 36.85 before silhouettes were split); the albedo
// itself scores 44.52 dB there with decals stacked per tap and creases split (41.42 with split
// silhouettes alone, 36.73 before). (The
// pixel's own light at the mixed pixels too scored 41.16 dB, but with 68 pixels worse than untouched;
// see below.)
TEST(BeautyAntialiased, RebuiltFarAboveUntouched) {
    const Measured& m = measure();
    RecordProperty("psnr_db", std::to_string(m.rebuilt_db));
    RecordProperty("untouched_psnr_db", std::to_string(m.untouched_db));
    EXPECT_GE(m.rebuilt_db, m.untouched_db + 15.0);
    EXPECT_GE(m.rebuilt_db, 36.78 - 0.5);
}

// Issue 14: no pixel gets worse than leaving it untouched (beyond the truth's noise, kNoise). With
// each pixel's own light this failed at 68 mixed pixels (silhouettes, creases), 32 of them even when
// fed the truth's own albedo: Cycles divides its light passes by the colour after filtering, so
// where light and the decal's change vary together inside the footprint the pixel's light is the
// wrong weight. Mixed pixels now take the least light around them (docs/profiles.md "Mixed
// pixels"), which undershoots rather than overshoots: no pixel is worse (the worst comes within
// 0.029 of the untouched error, under the noise), and the mixed pixels keep an update (leaving them
// untouched instead scored 33.10 dB). When the pixel filter first split silhouette pixels between
// their surfaces, 2 of them came out worse by 0.0341 at most (x 77, y 155: a face seen edge-on
// between the two surfaces); since a split must explain the pixel's normal (docs/pixel-filter.md
// "Silhouettes") none is, the worst coming within 0.0164 of the untouched error.
TEST(BeautyAntialiased, NoPixelWorseThanUntouched) {
    const Measured& m = measure();
    RecordProperty("worse_pixels", std::to_string(m.worse));
    RecordProperty("worst_excess", std::to_string(m.worst));
    EXPECT_LE(m.worst, kNoise);
    EXPECT_EQ(m.worse, 0u) << m.worse_mixed << " of them mixed, " << m.worse_albedo << " with the albedo off by > 0.01, "
                           << m.worse_formula << " worse even with the truth's albedo; worst by " << m.worst << " at x "
                           << m.worst_x << ", y " << m.worst_y;
}

}  // namespace
}  // namespace decalcomp
