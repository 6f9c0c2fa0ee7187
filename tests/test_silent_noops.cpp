// No silent no-ops: cameras no renderer writes are errors naming the file and field; an infinite
// far plane works; runs that would do nothing, or less than asked, warn and say what to check.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <OpenEXR/ImfChannelList.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "decalcomp/exr_file.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::shellQuote;

struct Sample {
    test::ScratchDir dir;
    std::string input, scene, camera;
    Sample() {
        fs::copy(test::dataPath("sample"), dir.path(), fs::copy_options::recursive);
        input = dir.file("gbuffer.exr");
        scene = dir.file("scene.json");
        camera = dir.file("camera.json");
    }
    test::CommandResult composite(const std::string& camera_path, const std::string& extra = "",
                                  const std::string& scene_path = "") const {
        return test::runCli("composite " + shellQuote(input) + " --decals " +
                            shellQuote(scene_path.empty() ? scene : scene_path) + " --camera " +
                            shellQuote(camera_path) + " --device cpu -o " + shellQuote(dir.file("out.exr")) + " " +
                            extra);
    }
    json cameraJson() const { return json::parse(std::ifstream(camera)); }
    std::string writeJson(const std::string& name, const json& doc) const {
        std::ofstream(dir.file(name)) << doc.dump(2);
        return dir.file(name);
    }
    // The input with its Z channel rewritten by `depth(pixel)`.
    void rewriteDepth(const std::function<float(std::size_t)>& depth) const {
        ExrImage image = readExr(input);
        for (ExrChannel& channel : image.parts[0].channels) {
            if (channel.name != "Z") continue;
            auto* samples = reinterpret_cast<float*>(channel.bytes.data());
            for (std::size_t i = 0; i < channel.bytes.size() / sizeof(float); ++i) samples[i] = depth(i);
        }
        writeExrAtomic(image, input);
    }
};

// Albedo samples of `path` that differ from the input's.
std::size_t changedAlbedoSamples(const std::string& input, const std::string& path) {
    const ExrImage a = readExr(input), b = readExr(path);
    std::size_t changed = 0;
    for (const char* name : {"albedo.R", "albedo.G", "albedo.B"}) {
        const ExrChannel &ca = test::channel(a, name), &cb = test::channel(b, name);
        for (std::size_t i = 0; i < ca.bytes.size(); i += 4)
            changed += std::memcmp(&ca.bytes[i], &cb.bytes[i], 4) != 0;
    }
    return changed;
}

void expectWarning(const test::CommandResult& r, const std::vector<std::string>& needles) {
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const std::size_t at = r.output.find("decalcomp: warning: ");
    ASSERT_NE(at, std::string::npos) << r.output;
    for (const std::string& needle : needles) EXPECT_NE(r.output.find(needle), std::string::npos) << needle << "\n" << r.output;
}

void expectInputError(const test::CommandResult& r, const std::string& file, const std::string& field) {
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find("decalcomp: error: " + file + ": " + field), std::string::npos) << r.output;
}

TEST(SilentNoOps, InfiniteFarProjectionComposites) {
    Sample s;
    json camera = s.cameraJson();
    const double a = camera["projection"][2][2], b = camera["projection"][2][3];
    const double near = b / (a - 1.0);
    camera["projection"][2] = {0.0, 0.0, -1.0, -2.0 * near};  // the limit far -> infinity
    const std::string infinite = s.writeJson("infinite.json", camera);
    ASSERT_EQ(s.composite(s.camera).exit_code, 0);
    const std::size_t finite_changes = changedAlbedoSamples(s.input, s.dir.file("out.exr"));
    const auto r = s.composite(infinite);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::size_t infinite_changes = changedAlbedoSamples(s.input, s.dir.file("out.exr"));
    // The sample's far plane (100) is beyond all its geometry, so the same pixels are decaled,
    // up to float rounding at decal edges.
    EXPECT_GT(finite_changes, 10000u);
    EXPECT_NEAR(double(infinite_changes), double(finite_changes), 0.005 * double(finite_changes));
}

TEST(SilentNoOps, FarBeforeNearIsAnError) {
    Sample s;
    json camera = s.cameraJson();
    const double n = 10.0, f = 1.0;  // OpenGL's z row for near 10, far 1
    camera["projection"][2] = {0.0, 0.0, -(f + n) / (f - n), -2.0 * f * n / (f - n)};
    const std::string path = s.writeJson("swapped.json", camera);
    const auto r = s.composite(path);
    expectInputError(r, path, "projection: far plane 1 is not beyond the near plane 10");
    EXPECT_FALSE(fs::exists(s.dir.file("out.exr")));
}

TEST(SilentNoOps, NegativeNearIsAnError) {
    Sample s;
    json camera = s.cameraJson();
    camera["projection"][2][2] = -double(camera["projection"][2][2]);
    const std::string path = s.writeJson("behind.json", camera);
    expectInputError(s.composite(path), path, "projection: near plane");
}

TEST(SilentNoOps, NonAffineWorldToCameraIsAnError) {
    Sample s;
    json camera = s.cameraJson();
    camera["world_to_camera"][3] = {0.0, 0.25, 0.0, 1.0};
    const std::string path = s.writeJson("projective.json", camera);
    expectInputError(s.composite(path), path, "world_to_camera: last row is (0, 0.25, 0, 1), not (0, 0, 0, 1)");
}

TEST(SilentNoOps, ProjectionWithAForeignWRowIsAnError) {
    Sample s;
    json camera = s.cameraJson();
    camera["projection"][3] = {0.0, 0.5, -1.0, 0.0};
    const std::string path = s.writeJson("tilted.json", camera);
    expectInputError(s.composite(path), path, "projection: last row is (0, 0.5, -1, 0)");
}

TEST(SilentNoOps, AllBackgroundDepthWarns) {
    Sample s;
    s.rewriteDepth([](std::size_t) { return 1e10f; });
    const auto r = s.composite(s.camera);
    expectWarning(r, {s.input + ": depth (Z): every pixel is background", "check --depth"});
}

TEST(SilentNoOps, NanAndNegativeDepthWarnWithCounts) {
    Sample s;
    const ExrImage original = readExr(s.input);
    const auto& z = test::channel(original, "Z");
    std::vector<float> depth(z.bytes.size() / 4);
    std::memcpy(depth.data(), z.bytes.data(), z.bytes.size());
    s.rewriteDepth([&](std::size_t i) {
        if (i < 100) return std::numeric_limits<float>::quiet_NaN();
        if (i < 130) return -depth[i];
        return depth[i];
    });
    const auto r = s.composite(s.camera);
    expectWarning(r, {s.input + ": depth (Z): 100 of 230400 pixels hold NaN depth",
                      s.input + ": depth (Z): 30 of 230400 pixels hold negative depth"});
}

TEST(SilentNoOps, ColourFileGivenAsDepthWarns) {
    Sample s;
    ExrImage image = readExr(s.input);
    ExrPart& part = image.parts[0];
    Imf::ChannelList kept;
    std::vector<ExrChannel> channels;
    for (const ExrChannel& channel : part.channels)
        if (channel.name == "R" || channel.name == "G" || channel.name == "B") {
            kept.insert(channel.name, part.header.channels()[channel.name]);
            channels.push_back(channel);
        }
    part.header.channels() = kept;
    part.channels = channels;
    const std::string rgb = s.dir.file("beauty.exr");
    writeExrAtomic(image, rgb);
    const auto r = s.composite(s.camera, "--pass depth=" + shellQuote(rgb));
    expectWarning(r, {rgb + ": --pass depth: took R for depth but the file also has B, G"});
}

TEST(SilentNoOps, DuplicateDecalNamesWarn) {
    Sample s;
    json scene = json::parse(std::ifstream(s.scene));
    scene["decals"][2]["name"] = scene["decals"][0]["name"];
    const std::string path = s.writeJson("dupes.json", scene);
    const auto r = s.composite(s.camera, "", path);
    expectWarning(r, {path + ": decals[2].name: 'floor_scorch' is also the name of decals[0]"});
}

TEST(SilentNoOps, RunChangingNoPixelWarns) {
    Sample s;
    json scene = json::parse(std::ifstream(s.scene));
    json far_away = scene["decals"][0];
    far_away["translate"] = {500.0, 500.0, 500.0};
    scene["decals"] = json::array({far_away});
    const std::string path = s.writeJson("far.json", scene);
    const auto r = s.composite(s.camera, "", path);
    expectWarning(r, {s.input + ": no decal changed any pixel: check"});
    EXPECT_EQ(test::readFileBytes(s.dir.file("out.exr")).size() > 0, true);
}

}  // namespace
}  // namespace decalcomp
