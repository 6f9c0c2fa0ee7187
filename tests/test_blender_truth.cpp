// The real-renderer check: composite the Blender sample's decals through the CLI and compare the
// DiffCol pass with Blender's own render of the same decals (data/blender/truth.exr).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

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

// Composites a sample folder's gbuffer.exr with the given scene (in the folder, or an absolute
// path) through the CLI into `out`.
void compositeSample(const std::string& folder, const std::string& scene, const std::string& out,
                     const std::string& extra = "-q") {
    const auto file = [&](const std::string& f) { return test::shellQuote(test::dataPath(folder + "/" + f)); };
    const std::string scene_file = scene.starts_with('/') ? test::shellQuote(scene) : file(scene);
    const auto run = test::runCli("composite " + file("gbuffer.exr") + " --decals " + scene_file + " --camera " +
                                  file("camera.json") + " --device cpu " + extra + " -o " + test::shellQuote(out));
    ASSERT_EQ(run.exit_code, 0) << run.output;
}

TEST(BlenderTruth, BoxDecalsMatchCyclesAbove40dB) {
    test::ScratchDir dir;
    const std::string out = dir.file("out.exr");
    ASSERT_NO_FATAL_FAILURE(compositeSample("blender", "scene.json", out));
    const ExrImage result = readExr(out);
    const ExrImage truth = readExr(test::dataPath("blender/truth.exr"));
    const Score score = scoreAgainstTruth(result, truth);
    EXPECT_GT(score.pixels, 3000u);
    EXPECT_GE(score.psnr, 40.0) << "over " << score.pixels / 3 << " decal pixels";
    RecordProperty("psnr_db", std::to_string(score.psnr));
    // The untouched input scores far lower: the test really measures the decals.
    const ExrImage input = readExr(test::dataPath("blender/gbuffer.exr"));
    EXPECT_LT(scoreAgainstTruth(input, truth).psnr, 25.0);
}

TEST(BlenderTruth, NeutralDecalFileLoadsAsIs) {
    // decals.json from the renderer sample, unconverted; linear filtering by default, so only
    // the >= 40 dB bar applies.
    test::ScratchDir dir;
    const std::string out = dir.file("out.exr");
    ASSERT_NO_FATAL_FAILURE(compositeSample("blender", "decals.json", out));
    EXPECT_GE(scoreAgainstTruth(readExr(out), readExr(test::dataPath("blender/truth.exr"))).psnr, 40.0);
}

TEST(BlenderTruth, UntouchedChannelsAreBitExact) {
    test::ScratchDir dir;
    const std::string out = dir.file("out.exr");
    ASSERT_NO_FATAL_FAILURE(compositeSample("blender", "scene.json", out));
    const ExrImage in = readExr(test::dataPath("blender/gbuffer.exr"));
    const ExrImage result = readExr(out);
    ASSERT_EQ(in.parts.size(), result.parts.size());
    EXPECT_EQ(in.parts[0].header.compression(), result.parts[0].header.compression());
    ASSERT_EQ(in.parts[0].channels.size(), result.parts[0].channels.size());
    std::size_t changed_channels = 0;
    for (std::size_t c = 0; c < in.parts[0].channels.size(); ++c) {
        const ExrChannel& a = in.parts[0].channels[c];
        const ExrChannel& b = result.parts[0].channels[c];
        EXPECT_EQ(a.qualified, b.qualified);
        EXPECT_EQ(a.type, b.type);
        const bool albedo = a.qualified.find("DiffCol") != std::string::npos;
        if (!albedo) {
            EXPECT_EQ(a.bytes, b.bytes) << a.qualified << " changed";
        }
        changed_channels += a.bytes != b.bytes;
    }
    EXPECT_EQ(changed_channels, 3u);  // exactly DiffCol R, G, B
}

// Every kind against Cycles: ../shared/data/blender-kinds (box, frustum, volume, cube decals).
TEST(BlenderTruth, EveryKindMatchesCycles) {
    test::ScratchDir dir;
    const std::string out = dir.file("out.exr");
    ASSERT_NO_FATAL_FAILURE(compositeSample("blender-kinds", "scene.json", out));
    const ExrImage result = readExr(out);
    const ExrImage truth = readExr(test::dataPath("blender-kinds/truth.exr"));
    // The volume is an analytic function in the truth: only trilinear filtering of its 32^3
    // samples gets above 55 dB (nearest voxels score about 46).
    const std::pair<const char*, double> bars[] = {{"Box", 40.0}, {"Frustum", 40.0}, {"Volume", 55.0}, {"Cube", 40.0}};
    for (const auto& [kind, bar] : bars) {
        const Score score = scoreAgainstTruth(result, truth, std::string("ViewLayer.DecalMask") + kind + ".X");
        EXPECT_GT(score.pixels, 300u) << kind;
        EXPECT_GE(score.psnr, bar) << kind << " over " << score.pixels / 3 << " pixels";
        RecordProperty(std::string("psnr_db_") + kind, std::to_string(score.psnr));
    }
}

// The cube blast with `linear` instead of Cycles' closest (the truth samples each face with
// closest, so any linear filter loses against it): seamless filtering keeps the cube's bar.
// Measured: seamless 54.45 dB; the per-face clamped lookup it replaced 54.46 dB. The nearest cube
// of EveryKindMatchesCycles is unchanged by seamless filtering: 93.04 dB before and after.
TEST(BlenderTruth, LinearCubeMatchesCycles) {
    test::ScratchDir dir;
    const std::string folder = test::dataPath("blender-kinds");
    nlohmann::json scene = nlohmann::json::parse(std::ifstream(folder + "/scene.json"));
    for (auto& [name, texture] : scene.at("textures").items())
        for (auto& [key, value] : texture.items()) {
            if (value.is_string() && key != "alpha") value = folder + "/" + value.get<std::string>();
            if (value.is_array())
                for (auto& face : value) face = folder + "/" + face.get<std::string>();
        }
    for (auto& decal : scene.at("decals"))
        if (decal.at("kind") == "cube") decal["filter"] = "linear";
    std::ofstream(dir.file("scene.json")) << scene.dump(2);
    ASSERT_NO_FATAL_FAILURE(compositeSample("blender-kinds", dir.file("scene.json"), dir.file("out.exr")));
    const Score score = scoreAgainstTruth(
        readExr(dir.file("out.exr")), readExr(test::dataPath("blender-kinds/truth.exr")), "ViewLayer.DecalMaskCube.X");
    EXPECT_GT(score.pixels, 300u);
    EXPECT_GE(score.psnr, 40.0) << "over " << score.pixels / 3 << " pixels";
    RecordProperty("psnr_db_cube_linear", std::to_string(score.psnr));
    std::printf("linear cube: %.2f dB over %zu pixels\n", score.psnr, score.pixels / 3);
}

// Blender's default pixel filter (Blackman-Harris 1.5 px, which Cycles doubles: blackman-harris:3)
// at 256 spp: ../shared/data/blender-aa. README: point-sampled nearest 28.6 dB, mip from the pixel
// footprint 39.9, decals composited at 4x and filtered like Cycles 46.2 (box 42.5, frustum 45.8,
// volume 58.7, cube 56.6). Issue 15's bars: 44 dB over the decal pixels, 40 for each kind.
TEST(BlenderTruth, AntialiasedFrameMatchesCycles) {
    test::ScratchDir dir;
    ASSERT_NO_FATAL_FAILURE(compositeSample("blender-aa", "scene.json", dir.file("out.exr"), ""));
    const ExrImage result = readExr(dir.file("out.exr"));
    const ExrImage truth = readExr(test::dataPath("blender-aa/truth.exr"));
    const Score all = scoreAgainstTruth(result, truth);
    std::printf("antialiased: %.2f dB over %zu decal pixels\n", all.psnr, all.pixels / 3);
    EXPECT_GE(all.psnr, 44.0);
    RecordProperty("psnr_db", std::to_string(all.psnr));
    for (const char* kind : {"Box", "Frustum", "Volume", "Cube"}) {
        const Score score = scoreAgainstTruth(result, truth, std::string("ViewLayer.DecalMask") + kind + ".X");
        std::printf("  %s: %.2f dB over %zu pixels\n", kind, score.psnr, score.pixels / 3);
        EXPECT_GT(score.pixels, 300u) << kind;
        EXPECT_GE(score.psnr, 40.0) << kind;
        RecordProperty(std::string("psnr_db_") + kind, std::to_string(score.psnr));
    }
    // point-sampled, the same frame scores what the README measured for nearest texels
    ASSERT_NO_FATAL_FAILURE(compositeSample("blender-aa", "scene.json", dir.file("point.exr"), "-q --pixel-filter none"));
    const Score point = scoreAgainstTruth(readExr(dir.file("point.exr")), truth);
    std::printf("point-sampled: %.2f dB\n", point.psnr);
    EXPECT_LT(point.psnr, 32.0);
    // Mixed pixels (an averaged normal, or a depth jump to a neighbour: silhouettes and creases)
    // should come out no worse than point-sampled ones (docs/pixel-filter.md "Mixed pixels").
    // Tolerance 0.03 (the 256-spp truth's own noise is about 0.003 rms per channel). Measured over
    // 1404 such pixels: with the averaged plane at silhouettes none (worst 0.0202) at 34.06 dB; with
    // silhouettes split between their surfaces 41.49 dB, and 1 pixel worse, by 0.122 (x 108, y 117,
    // where a third surface shows between the two the split takes); with creases split too 46.33 dB,
    // the same pixel worse; since a split must explain the pixel's normal 47.06 dB and none worse
    // (worst by 0.0249 on the 2-core AVX-512 VM: 0.025 left no room for another CPU's rounding, and
    // the test failed once in a full run; the pixels that failed a split were worse by 0.12).
    const MixedPixels mixed = compareMixedPixels(test::dataPath("blender-aa/gbuffer.exr"), result,
                                                 readExr(dir.file("point.exr")), truth, 0.03);
    std::printf("mixed pixels: %zu, worse than point-sampled by > 0.03: %zu (worst by %.4f); filtered %.2f dB, "
                "point %.2f dB\n",
                mixed.pixels, mixed.worse, mixed.worst_excess, mixed.filtered_psnr, mixed.point_psnr);
    EXPECT_GT(mixed.pixels, 500u);
    EXPECT_EQ(mixed.worse, 0u) << "worst by " << mixed.worst_excess;
    EXPECT_GT(mixed.filtered_psnr, mixed.point_psnr);
    EXPECT_GE(mixed.filtered_psnr, 47.06 - 0.5);
}

// The closed form (`--pixel-filter blackman-harris:3:fast`, docs/pixel-filter.md "Integrated
// evaluation") on the same frame: each decal once per pixel. Measured: 49.90 dB (box 48.20, frustum
// 49.02, volume 51.90, cube 49.12) against the taps' 54.10, at a quarter of their kernel time
// (docs/benchmarks.md). It meets issue 15's bars too.
TEST(BlenderTruth, AntialiasedFrameFastMatchesCycles) {
    test::ScratchDir dir;
    ASSERT_NO_FATAL_FAILURE(
        compositeSample("blender-aa", "scene.json", dir.file("out.exr"), "-q --pixel-filter blackman-harris:3:fast"));
    const ExrImage truth = readExr(test::dataPath("blender-aa/truth.exr"));
    const ExrImage result = readExr(dir.file("out.exr"));
    const Score all = scoreAgainstTruth(result, truth);
    std::printf("antialiased, fast: %.2f dB over %zu decal pixels\n", all.psnr, all.pixels / 3);
    EXPECT_GE(all.psnr, 49.90 - 0.3);
    EXPECT_GE(all.psnr, 44.0);
    for (const char* kind : {"Box", "Frustum", "Volume", "Cube"}) {
        const Score score = scoreAgainstTruth(result, truth, std::string("ViewLayer.DecalMask") + kind + ".X");
        std::printf("  %s: %.2f dB over %zu pixels\n", kind, score.psnr, score.pixels / 3);
        EXPECT_GE(score.psnr, 40.0) << kind;
    }
}

// The run says which filter it integrated over and why: the antialiased frame's normals are
// averaged (shorter than 1) at edges, so Blender's default applies; the 1-spp frames' normals are
// unit vectors with hard edges. (Cycles does not filter its object-id pass: both frames' ids are
// whole numbers.)
TEST(BlenderTruth, PixelFilterFollowsTheFrame) {
    test::ScratchDir dir;
    const auto run = [&](const std::string& folder) {
        const auto file = [&](const std::string& f) { return test::shellQuote(test::dataPath(folder + "/" + f)); };
        return test::runCli("composite " + file("gbuffer.exr") + " --decals " + file("scene.json") + " --camera " +
                            file("camera.json") + " --device cpu -o " + test::shellQuote(dir.file(folder + ".exr")));
    };
    const auto aa = run("blender-aa");
    ASSERT_EQ(aa.exit_code, 0) << aa.output;
    EXPECT_NE(aa.output.find("pixel filter: blackman-harris:3 (profile blender)"), std::string::npos) << aa.output;
    const auto kinds = run("blender-kinds");
    ASSERT_EQ(kinds.exit_code, 0) << kinds.output;
    EXPECT_NE(kinds.output.find("pixel filter: none (the normal pass has hard edges: "), std::string::npos)
        << kinds.output;
}

// `--pixel-filter auto:fast` chooses the filter as auto does and evaluates it in closed form: on the
// antialiased frame the profile's blackman-harris:3, as `:fast` (bit for bit the explicit spelling's
// result); on an unfiltered frame still none.
TEST(BlenderTruth, AutoFastChoosesLikeAutoAndEvaluatesFast) {
    test::ScratchDir dir;
    const auto run = [&](const std::string& folder, const std::string& filter, const std::string& out) {
        const auto file = [&](const std::string& f) { return test::shellQuote(test::dataPath(folder + "/" + f)); };
        return test::runCli("composite " + file("gbuffer.exr") + " --decals " + file("scene.json") + " --camera " +
                            file("camera.json") + " --device cpu --beauty off --pixel-filter " + filter + " -o " +
                            test::shellQuote(dir.file(out)));
    };
    const auto chosen = run("blender-aa", "auto:fast", "auto.exr");
    ASSERT_EQ(chosen.exit_code, 0) << chosen.output;
    EXPECT_NE(chosen.output.find("pixel filter: blackman-harris:3:fast (profile blender)"), std::string::npos)
        << chosen.output;
    const auto named = run("blender-aa", "blackman-harris:3:fast", "named.exr");
    ASSERT_EQ(named.exit_code, 0) << named.output;
    const auto taps = run("blender-aa", "blackman-harris:3", "taps.exr");
    ASSERT_EQ(taps.exit_code, 0) << taps.output;
    const ExrImage a = readExr(dir.file("auto.exr")), b = readExr(dir.file("named.exr")), c = readExr(dir.file("taps.exr"));
    std::vector<float> x, y, z;
    ASSERT_NE(findFloatChannel(a, "ViewLayer.DiffCol.R", x), nullptr);
    ASSERT_NE(findFloatChannel(b, "ViewLayer.DiffCol.R", y), nullptr);
    ASSERT_NE(findFloatChannel(c, "ViewLayer.DiffCol.R", z), nullptr);
    EXPECT_EQ(x, y);
    EXPECT_NE(x, z);  // the closed form, not the taps
    const auto kinds = run("blender-kinds", "auto:fast", "kinds.exr");
    ASSERT_EQ(kinds.exit_code, 0) << kinds.output;
    EXPECT_NE(kinds.output.find("pixel filter: none (the normal pass has hard edges: "), std::string::npos)
        << kinds.output;
}

// Batch carries the filter like composite: a one-frame sequence of the antialiased frame gives the
// composite's albedo bit for bit, under auto and under an explicit filter.
TEST(BlenderTruth, BatchIntegratesOverTheSameFilter) {
    test::ScratchDir dir;
    const auto file = [&](const std::string& f) { return test::shellQuote(test::dataPath("blender-aa/" + f)); };
    std::filesystem::copy_file(test::dataPath("blender-aa/gbuffer.exr"), dir.file("g.0001.exr"));
    for (const std::string filter : {"auto", "gaussian:2", "auto:fast"}) {
        const std::string options = " --decals " + file("scene.json") + " --camera " + file("camera.json") +
                                    " --device cpu -q --pixel-filter " + filter;
        const auto single = test::runCli("composite " + file("gbuffer.exr") + options + " -o " +
                                         test::shellQuote(dir.file("single.exr")));
        ASSERT_EQ(single.exit_code, 0) << single.output;
        const auto batch = test::runCli("batch " + test::shellQuote(dir.file("g.####.exr")) + options + " -o " +
                                        test::shellQuote(dir.file("b.####.exr")));
        ASSERT_EQ(batch.exit_code, 0) << batch.output;
        const ExrImage a = readExr(dir.file("single.exr")), b = readExr(dir.file("b.0001.exr"));
        std::vector<float> x, y;
        for (const char* c : {"R", "G", "B"}) {
            const std::string name = std::string("ViewLayer.DiffCol.") + c;
            ASSERT_NE(findFloatChannel(a, name, x), nullptr);
            ASSERT_NE(findFloatChannel(b, name, y), nullptr);
            EXPECT_EQ(x, y) << filter << " " << name;
        }
        const Score score = scoreAgainstTruth(b, readExr(test::dataPath("blender-aa/truth.exr")));
        EXPECT_GE(score.psnr, 40.0) << filter;  // filtered either way (point-sampled: 28.6)
    }
}

}  // namespace
}  // namespace decalcomp
