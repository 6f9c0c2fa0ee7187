// Provenance (provenance.hpp): every composited file records the version, the scene's
// fingerprint and file, and the decals; compositing the same scene over its own output is refused
// without --force (exit 2, nothing written); other scenes stack and the history keeps them all.
#include <gtest/gtest.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "decalcomp/exr_file.hpp"
#include "decalcomp/provenance.hpp"
#include "decalcomp/scene.hpp"
#include "decalcomp/version.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::shellQuote;

struct Sample {
    test::ScratchDir dir;
    std::string input = test::dataPath("sample/gbuffer.exr"), scene = test::dataPath("sample/scene.json"),
                camera = test::dataPath("sample/camera.json");
    std::string composite(const std::string& in, const std::string& out, const std::string& extra = "",
                          const std::string& scene_file = "") const {
        return "composite " + shellQuote(in) + " --decals " + shellQuote(scene_file.empty() ? scene : scene_file) +
               " --camera " + shellQuote(camera) + " --device cpu -q -o " + shellQuote(out) + " " + extra;
    }
};

ProvenanceRecord recordOf(const std::string& path) {
    const auto headers = readExrHeaders(path);
    const auto record = readProvenance(headers.front(), path);
    if (!record) throw std::runtime_error(path + ": no decalcomp record");
    return *record;
}

std::vector<std::string> decalNames(const DecalScene& scene) {
    std::vector<std::string> names;
    for (const Decal& d : scene.decals) names.push_back(d.name);
    return names;
}

TEST(Provenance, FingerprintIgnoresLayoutButNotContent) {
    const std::string a = R"({"decals": [{"translate": [0, 0, 0], "affects": {"roughness": {"value": 0.5}}}]})";
    const std::string b = "{\n  \"decals\" : [ { \"affects\": {\"roughness\": {\"value\": 0.5}},\n \"translate\": [0,0,0] } ]\n}";
    const std::string c = R"({"decals": [{"translate": [0, 0, 0], "affects": {"roughness": {"value": 0.6}}}]})";
    EXPECT_EQ(parseScene(a, "a", ".").fingerprint, parseScene(b, "b", ".").fingerprint);
    EXPECT_NE(parseScene(a, "a", ".").fingerprint, parseScene(c, "c", ".").fingerprint);
    // FNV-1a 64 of "" and "a", the published test vectors.
    EXPECT_EQ(sceneFingerprint(""), "fnv1a64:cbf29ce484222325");
    EXPECT_EQ(sceneFingerprint("a"), "fnv1a64:af63dc4c8601ec8c");
}

TEST(Provenance, OutputRecordsVersionSceneAndDecalsAndKeepsTheInputsAttributes) {
    Sample s;
    const std::string out = s.dir.file("out.exr");
    const auto r = test::runCli(s.composite(s.input, out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const DecalScene scene = loadScene(s.scene);
    const ProvenanceRecord record = recordOf(out);
    EXPECT_EQ(record.version, kVersion);
    EXPECT_EQ(record.scene, scene.fingerprint);
    EXPECT_EQ(record.scene_file, s.scene);
    EXPECT_EQ(record.decals, decalNames(scene));
    EXPECT_EQ(record.scenes, std::vector<std::string>{scene.fingerprint});
    // Every attribute of the input is still there, with its value's type.
    const Imf::Header in = readExrHeaders(s.input).front(), written = readExrHeaders(out).front();
    for (auto it = in.begin(); it != in.end(); ++it) {
        const auto kept = written.find(it.name());
        ASSERT_NE(kept, written.end()) << it.name();
        EXPECT_STREQ(kept.attribute().typeName(), it.attribute().typeName()) << it.name();
    }
    EXPECT_FALSE(readProvenance(in, s.input).has_value());
}

TEST(Provenance, SameSceneOverItsOutputIsRefusedUnlessForced) {
    Sample s;
    const std::string first = s.dir.file("first.exr"), second = s.dir.file("second.exr");
    ASSERT_EQ(test::runCli(s.composite(s.input, first)).exit_code, 0);
    const auto refused = test::runCli(s.composite(first, second));
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find(first + ": already composited with this scene"), std::string::npos) << refused.output;
    EXPECT_NE(refused.output.find("--force"), std::string::npos) << refused.output;
    EXPECT_FALSE(fs::exists(second));
    EXPECT_EQ(test::occurrences(refused.output, "\n"), 1u) << refused.output;  // one line

    const auto forced = test::runCli(s.composite(first, second, "--force"));
    ASSERT_EQ(forced.exit_code, 0) << forced.output;
    const std::string fingerprint = loadScene(s.scene).fingerprint;
    EXPECT_EQ(recordOf(second).scenes, (std::vector<std::string>{fingerprint, fingerprint}));
}

TEST(Provenance, AnotherSceneStacksAndTheHistoryKeepsBoth) {
    Sample s;
    const std::string other = s.dir.file("wet.json");
    std::ofstream(other) << R"({"decals": [{"name": "wet", "translate": [0, 0, 0], "scale": [40, 40, 40],
                                "affects": {"roughness": {"value": 0.05}}}]})";
    const std::string first = s.dir.file("first.exr"), second = s.dir.file("second.exr");
    ASSERT_EQ(test::runCli(s.composite(s.input, first)).exit_code, 0);
    const auto r = test::runCli(s.composite(first, second, "", other));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const ProvenanceRecord record = recordOf(second);
    EXPECT_EQ(record.scene, loadScene(other).fingerprint);
    EXPECT_EQ(record.decals, std::vector<std::string>{"wet"});
    EXPECT_EQ(record.scenes, (std::vector<std::string>{loadScene(s.scene).fingerprint, loadScene(other).fingerprint}));
    const auto info = test::runCli("info " + shellQuote(second) + " --camera " + shellQuote(s.camera));
    ASSERT_EQ(info.exit_code, 0) << info.output;
    EXPECT_NE(info.output.find("composited by decalcomp " + std::string(kVersion) + " with " + other), std::string::npos)
        << info.output;
    EXPECT_NE(info.output.find("1 decal(s): wet"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("scenes composited into it, oldest first: " + loadScene(s.scene).fingerprint + ", " +
                               loadScene(other).fingerprint),
              std::string::npos)
        << info.output;
}

TEST(Provenance, EveryChunkEncodedWriteCarriesTheRecordToo) {
    Sample s;  // --add-channels writes every chunk through the full encoder, not the chunk copier
    const std::string out = s.dir.file("out.exr");
    const auto r = test::runCli(s.composite(s.input, out, "--add-channels emission"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(recordOf(out).scene, loadScene(s.scene).fingerprint);
}

TEST(Provenance, BatchRefusesFramesThatHoldTheSceneUnlessForced) {
    Sample s;
    fs::create_directories(s.dir.file("in"));
    ASSERT_EQ(test::runCli(s.composite(s.input, s.dir.file("in/f.0001.exr"))).exit_code, 0);
    const std::string batch = "batch " + shellQuote(s.dir.file("in/f.####.exr")) + " -o " +
                              shellQuote(s.dir.file("out/f.####.exr")) + " --decals " + shellQuote(s.scene) +
                              " --camera " + shellQuote(s.camera) + " --device cpu -q";
    const auto refused = test::runCli(batch);
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("already composited with this scene"), std::string::npos) << refused.output;
    EXPECT_FALSE(fs::exists(s.dir.file("out/f.0001.exr")));
    ASSERT_EQ(test::runCli(batch + " --force").exit_code, 0);
    EXPECT_EQ(recordOf(s.dir.file("out/f.0001.exr")).scenes.size(), 2u);
}

TEST(Provenance, MalformedRecordIsAnInputErrorNamingTheAttribute) {
    Imf::Header header(4, 4);
    header.insert("decalcomp/scene", Imf::StringAttribute("fnv1a64:0"));
    header.insert("decalcomp/decals", Imf::StringAttribute("not json"));
    const std::string message = test::errorMessage(ErrorKind::Input, [&] { readProvenance(header, "f.exr"); });
    EXPECT_EQ(message, "f.exr: header attribute decalcomp/decals: expected a JSON array of strings");
}

}  // namespace
}  // namespace decalcomp
