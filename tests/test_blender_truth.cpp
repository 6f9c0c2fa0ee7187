// The real-renderer check: composite the Blender sample's decals through the CLI and compare the
// DiffCol pass with Blender's own render of the same decals (data/blender/truth.exr).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "decalcomp/exr_file.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

const std::vector<float>* findFloatChannel(const ExrImage& image, const std::string& name, std::vector<float>& storage) {
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels)
            if (c.qualified == name && c.type == SampleType::Float) {
                storage.resize(c.bytes.size() / sizeof(float));
                std::memcpy(storage.data(), c.bytes.data(), c.bytes.size());
                return &storage;
            }
    return nullptr;
}

struct Score {
    double psnr = 0;
    std::size_t pixels = 0;
};

// PSNR (peak 1) of DiffCol R,G,B over the pixels where the truth's mask channel > 0.5.
Score scoreAgainstTruth(const ExrImage& result, const ExrImage& truth, const std::string& mask_channel = "ViewLayer.DecalMask.X") {
    std::vector<float> mask, a, b;
    EXPECT_NE(findFloatChannel(truth, mask_channel, mask), nullptr) << mask_channel;
    double squared = 0;
    Score score;
    for (const char* c : {"R", "G", "B"}) {
        const std::string name = std::string("ViewLayer.DiffCol.") + c;
        EXPECT_NE(findFloatChannel(result, name, a), nullptr) << name;
        EXPECT_NE(findFloatChannel(truth, name, b), nullptr) << name;
        for (std::size_t i = 0; i < mask.size(); ++i)
            if (mask[i] > 0.5f) {
                squared += double(a[i] - b[i]) * double(a[i] - b[i]);
                ++score.pixels;
            }
    }
    score.psnr = 10.0 * std::log10(double(score.pixels) / std::max(squared, 1e-30));
    return score;
}

// Composites a sample folder's gbuffer.exr with the given scene (in the folder, or an absolute
// path) through the CLI into `out`.
void compositeSample(const std::string& folder, const std::string& scene, const std::string& out) {
    const auto file = [&](const std::string& f) { return test::shellQuote(test::dataPath(folder + "/" + f)); };
    const std::string scene_file = scene.starts_with('/') ? test::shellQuote(scene) : file(scene);
    const auto run = test::runCli("composite " + file("gbuffer.exr") + " --decals " + scene_file + " --camera " +
                                  file("camera.json") + " --device cpu -q -o " + test::shellQuote(out));
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

}  // namespace
}  // namespace decalcomp
