// Decal masks: object-id and Cryptomatte weights on the Blender sample (a decal across floor and
// wall restricted to one of them), coverage sums on small synthetic files, MurmurHash3, and the
// errors and warnings bad input gets.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <nlohmann/json.hpp>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/masks.hpp"
#include "decalcomp/scene.hpp"
#include "support/cryptomatte_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using json = nlohmann::json;
using namespace test;  // the synthetic Cryptomatte files of support/cryptomatte_fixture.hpp

ComputeDevice& cpuDevice() {
    static ComputeDevice device("cpu");
    return device;
}

// Object indices (IndexOB) of the Blender sample, as its Cryptomatte manifest names them.
enum BlenderObject { kBackground = 0, kFloor = 1, kWall = 2, kSphere = 3, kBox = 4, kBarrel = 5 };

// ---- the Blender sample -------------------------------------------------------------------

struct BlenderSample {
    ExrImage image;
    ChannelMapping mapping;
    GBuffer gbuffer;
    Camera camera;
    std::vector<int> object;  // IndexOB per pixel
};

const BlenderSample& blender() {
    static const BlenderSample sample = [] {
        BlenderSample s;
        s.image = readExr(test::dataPath("blender/gbuffer.exr"));
        s.mapping = mapChannels(s.image, MappingOptions{});
        s.gbuffer = extractGBuffer(s.image, s.mapping);
        s.camera = loadCameraJson(test::dataPath("blender/camera.json"));
        for (float v : s.gbuffer.planes.at(Attribute::ObjectId).samples) s.object.push_back(int(v));
        return s;
    }();
    return sample;
}

// The sample scene's corner_checker decal (it covers both the floor and the back wall), alone,
// with `mask` (JSON text; empty = no mask).
std::string cornerScene(const ScratchDir& dir, const std::string& mask) {
    const json sample = json::parse(std::ifstream(test::dataPath("blender/scene.json")));
    json decal = sample.at("decals").at(1);
    EXPECT_EQ(decal.at("name"), "corner_checker");
    if (!mask.empty()) decal["mask"] = json::parse(mask);
    const json scene = {{"textures", {{"checker", {{"albedo", test::dataPath("blender/decal_checker.png")}}}}},
                        {"decals", json::array({decal})}};
    const std::string path = dir.file("scene.json");
    std::ofstream(path) << scene.dump(2);
    return path;
}

struct MaskedRun {
    Plane before, after;  // albedo
    std::vector<float> weights;  // the decal's mask plane (all 1 without a mask)
    std::vector<std::string> warnings;
};

MaskedRun compositeCorner(const std::string& mask) {
    const BlenderSample& s = blender();
    ScratchDir dir;
    const DecalScene scene = loadScene(cornerScene(dir, mask));
    GBuffer frame = s.gbuffer;
    MaskedRun run;
    evaluateMasks(s.image, s.mapping, scene, frame, &run.warnings);
    EXPECT_EQ(frame.mask_weights.size(), scene.masks.size());
    run.weights = frame.mask_weights.empty() ? std::vector<float>(frame.pixelCount(), 1.0f)
                                             : frame.mask_weights.at(0).samples;
    static Compositor compositor(cpuDevice());  // kernels built once per test process
    compositor.setScene(scene);
    run.before = frame.planes.at(Attribute::Albedo);
    compositor.composite(frame, s.camera);
    run.after = frame.planes.at(Attribute::Albedo);
    return run;
}

bool samePixel(const Plane& a, const Plane& b, std::size_t i) {
    return std::memcmp(&a.samples[i * 3], &b.samples[i * 3], 3 * sizeof(float)) == 0;
}

// Pixels of each object whose albedo the run changed.
std::map<int, std::size_t> changedPerObject(const MaskedRun& run) {
    std::map<int, std::size_t> changed;
    const auto& object = blender().object;
    for (std::size_t i = 0; i < object.size(); ++i) changed[object[i]] += !samePixel(run.before, run.after, i);
    return changed;
}

const MaskedRun& unmaskedCorner() {
    static const MaskedRun run = compositeCorner("");
    return run;
}

TEST(BlenderMasks, UnmaskedDecalCoversFloorAndWall) {
    const auto changed = changedPerObject(unmaskedCorner());
    EXPECT_GT(changed.at(kFloor), 500u);
    EXPECT_GT(changed.at(kWall), 500u);
}

// Pixels of `kept` objects equal the unmasked result, every other pixel is bit-identical to the input.
void expectOnly(const MaskedRun& run, const std::set<int>& kept) {
    const MaskedRun& full = unmaskedCorner();
    const auto& object = blender().object;
    std::size_t changed = 0;
    for (std::size_t i = 0; i < object.size(); ++i) {
        if (kept.count(object[i])) {
            ASSERT_TRUE(samePixel(run.after, full.after, i)) << "pixel " << i << " of object " << object[i];
            changed += !samePixel(run.before, run.after, i);
        } else {
            ASSERT_TRUE(samePixel(run.after, run.before, i)) << "pixel " << i << " of object " << object[i];
        }
    }
    if (!kept.empty()) {
        EXPECT_GT(changed, 500u);
    }
}

TEST(BlenderMasks, CryptomatteNameRestrictsTheDecalToTheWall) {
    const MaskedRun run = compositeCorner(R"({"cryptomatte": {"layer": "CryptoObject", "names": ["Wall"]}})");
    EXPECT_TRUE(run.warnings.empty());
    expectOnly(run, {kWall});
}

TEST(BlenderMasks, IndexObRestrictsTheDecalToTheWall) {
    const MaskedRun run = compositeCorner(R"({"ids": [2]})");
    EXPECT_TRUE(run.warnings.empty());
    expectOnly(run, {kWall});
}

TEST(BlenderMasks, ExcludeIdsKeepTheWallUntouched) {
    expectOnly(compositeCorner(R"({"exclude_ids": [2]})"), {kBackground, kFloor, kSphere, kBox, kBarrel});
    expectOnly(compositeCorner(R"({"ids": [1, 2], "exclude_ids": [2]})"), {kFloor});
}

TEST(BlenderMasks, WildcardsSelectByPattern) {
    expectOnly(compositeCorner(R"({"cryptomatte": {"names": ["W*"]}})"), {kWall});
    expectOnly(compositeCorner(R"({"cryptomatte": {"names": ["Fl??r"]}})"), {kFloor});
    expectOnly(compositeCorner(R"({"cryptomatte": {"names": ["[FW]*"]}})"), {kFloor, kWall});
    expectOnly(compositeCorner(R"({"cryptomatte": {"names": ["Wall", "Floor"]}})"), {kFloor, kWall});
}

TEST(BlenderMasks, MaterialLayerSelectsByMaterialName) {
    expectOnly(compositeCorner(R"({"cryptomatte": {"layer": "CryptoMaterial", "names": ["M_Wall"]}})"), {kWall});
    // The full, view-layer-prefixed name works too.
    expectOnly(compositeCorner(R"({"cryptomatte": {"layer": "ViewLayer.CryptoMaterial", "names": ["M_Fl*"]}})"),
               {kFloor});
}

TEST(BlenderMasks, IdsAndCryptomatteMultiply) {
    expectOnly(compositeCorner(R"({"ids": [1, 2], "cryptomatte": {"names": ["Wall"]}})"), {kWall});
    expectOnly(compositeCorner(R"({"ids": [1], "cryptomatte": {"names": ["Wall"]}})"), {});
}

// With one sample per pixel every coverage is 0 or 1: each object's Cryptomatte weight must be
// exactly its IndexOB region. Box's hash 803b1009 has a zero exponent, so it also checks the
// specification's float conversion (its pixels hold 80bb1009).
TEST(BlenderMasks, CryptomatteWeightsEqualTheIndexObRegions) {
    const BlenderSample& s = blender();
    const std::map<std::string, int> objects = {
        {"Floor", kFloor}, {"Wall", kWall}, {"Sphere", kSphere}, {"Box", kBox}, {"Barrel", kBarrel}};
    DecalScene scene;
    for (const auto& [name, index] : objects) {
        scene.masks.push_back(DecalMask{{}, {}, "CryptoObject", {name}});
        scene.masks.push_back(DecalMask{{index}, {}, "", {}});
        scene.decals.push_back(maskedDecal(name, int(scene.masks.size()) - 2));
    }
    GBuffer frame = s.gbuffer;
    std::vector<std::string> warnings;
    evaluateMasks(s.image, s.mapping, scene, frame, &warnings);
    EXPECT_TRUE(warnings.empty());
    ASSERT_EQ(frame.mask_weights.size(), scene.masks.size());
    for (std::size_t m = 0; m < scene.masks.size(); m += 2) {
        const Plane& crypto = frame.mask_weights[m];
        const Plane& ids = frame.mask_weights[m + 1];
        ASSERT_EQ(crypto.components, 1);
        ASSERT_EQ(crypto.samples.size(), s.gbuffer.pixelCount());
        std::size_t inside = 0;
        for (std::size_t i = 0; i < crypto.samples.size(); ++i) {
            const float expected = s.object[i] == scene.masks[m + 1].include_ids[0] ? 1.0f : 0.0f;
            ASSERT_EQ(crypto.samples[i], expected) << scene.masks[m].cryptomatte_names[0] << " pixel " << i;
            ASSERT_EQ(ids.samples[i], expected) << "pixel " << i;
            inside += expected > 0;
        }
        EXPECT_GT(inside, 1000u) << scene.masks[m].cryptomatte_names[0];
    }
}

TEST(BlenderMasks, NameThatMatchesNothingWarns) {
    const MaskedRun run = compositeCorner(R"({"cryptomatte": {"names": ["Wall", "Wal*x"]}})");
    ASSERT_EQ(run.warnings.size(), 1u);
    EXPECT_EQ(run.warnings[0].rfind(test::dataPath("blender/gbuffer.exr") + ": ", 0), 0u) << "names the EXR first";
    EXPECT_NE(run.warnings[0].find("decal 'corner_checker': mask.cryptomatte.names[1]: 'Wal*x' matches nothing in "
                                   "ViewLayer.CryptoObject"),
              std::string::npos)
        << run.warnings[0];
    EXPECT_NE(run.warnings[0].find("check the pattern"), std::string::npos) << run.warnings[0];
    EXPECT_NE(run.warnings[0].find("Floor"), std::string::npos) << "should list the names present";
    expectOnly(run, {kWall});
    // A literal name that is neither in the manifest nor in any pixel warns too.
    const MaskedRun none = compositeCorner(R"({"cryptomatte": {"names": ["Roof"]}})");
    ASSERT_EQ(none.warnings.size(), 1u);
    EXPECT_NE(none.warnings[0].find("'Roof' matches nothing"), std::string::npos) << none.warnings[0];
    expectOnly(none, {});
}

TEST(BlenderMasks, UnknownLayerListsThoseThatExist) {
    try {
        compositeCorner(R"({"cryptomatte": {"layer": "CryptoAsset", "names": ["Wall"]}})");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        EXPECT_NE(msg.find("gbuffer.exr"), std::string::npos) << msg;
        EXPECT_NE(msg.find("unknown Cryptomatte layer 'CryptoAsset'"), std::string::npos) << msg;
        EXPECT_NE(msg.find("ViewLayer.CryptoObject"), std::string::npos) << msg;
        EXPECT_NE(msg.find("ViewLayer.CryptoMaterial"), std::string::npos) << msg;
    }
}

// ---- MurmurHash3 and the float conversion ---------------------------------------------------

TEST(Cryptomatte, MurmurHashEqualsTheBlenderManifests) {
    const std::vector<CryptomatteLayer> layers = cryptomatteLayers({blender().image});
    ASSERT_EQ(layers.size(), 2u);
    std::size_t names = 0;
    for (const CryptomatteLayer& layer : layers) {
        EXPECT_EQ(layer.hash, "MurmurHash3_32");
        EXPECT_EQ(layer.conversion, "uint32_to_float32");
        const CryptomatteManifest manifest = cryptomatteManifest(layer);
        EXPECT_TRUE(manifest.warnings.empty());
        for (const auto& [name, hash] : manifest.names) {
            EXPECT_EQ(murmurHash3_32(name), hash) << name;
            ++names;
        }
        // Blender's metadata key is the first 7 hex digits of the layer name's hash.
        EXPECT_EQ(fmt::format("{:08x}", murmurHash3_32(layer.name)).substr(0, 7), layer.key) << layer.name;
    }
    EXPECT_EQ(names, 5u + 13u);
}

TEST(Cryptomatte, MurmurHashKnownValues) {
    EXPECT_EQ(murmurHash3_32(""), 0u);
    EXPECT_EQ(murmurHash3_32("", 1), 0x514e28b7u);
    EXPECT_EQ(murmurHash3_32("", 0xffffffffu), 0x81f16f39u);
    EXPECT_EQ(murmurHash3_32("The quick brown fox jumps over the lazy dog"), 0x2e4ff723u);
    // Every tail length hashes differently and deterministically.
    std::set<std::uint32_t> seen;
    for (const char* s : {"a", "ab", "abc", "abcd", "abcde"}) seen.insert(murmurHash3_32(s));
    EXPECT_EQ(seen.size(), 5u);
}

TEST(Cryptomatte, FloatConversionClampsTheExponent) {
    EXPECT_EQ(cryptomatteBitsFromHash(0x2c388f97u), 0x2c388f97u);  // ordinary: unchanged
    EXPECT_EQ(cryptomatteBitsFromHash(0x803b1009u), 0x80bb1009u);  // exponent 0 -> 1
    EXPECT_EQ(cryptomatteBitsFromHash(0x7f812345u), 0x7f012345u);  // exponent 255 -> 254
    EXPECT_EQ(cryptomatteBitsFromHash(0u), 0x00800000u);           // never zero
    const float f = cryptomatteFloatFromHash(0x803b1009u);
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    EXPECT_EQ(bits, 0x80bb1009u);
}

// ---- small synthetic files --------------------------------------------------------------------

TEST(SyntheticMasks, CoverageIsSummedOverMatchingRanks) {
    ScratchDir dir;
    const std::string path = writeSynthetic(dir.file("c.exr"), twoRankLayer("CryptoObject"),
                                            layerMetadata("CryptoObject", manifestOf({"A", "B", "C", "D"})));
    const Evaluated e = evaluate(path, {crypto({"A"}), crypto({"A", "C"}), crypto({"B", "D"}), crypto({"*"}),
                                        crypto({"C"})});
    ASSERT_EQ(e.weights.size(), 5u);
    EXPECT_TRUE(e.warnings.empty());
    const auto w = [&](int m, std::size_t pixel) { return e.weights[std::size_t(m)].samples[pixel]; };
    EXPECT_FLOAT_EQ(w(0, 0), 0.5f);
    EXPECT_FLOAT_EQ(w(0, 1), 0.4f);
    EXPECT_FLOAT_EQ(w(1, 0), 0.65f);   // rank 0 + rank 2 (second channel set)
    EXPECT_FLOAT_EQ(w(1, 1), 1.0f);
    EXPECT_FLOAT_EQ(w(2, 0), 0.35f);   // rank 1 + rank 3 (b/a of both sets)
    EXPECT_FLOAT_EQ(w(2, 2), 1.0f);
    EXPECT_FLOAT_EQ(w(3, 0), 1.0f);
    EXPECT_FLOAT_EQ(w(4, 0), 0.15f);
    for (int m = 0; m < 5; ++m)
        for (std::size_t pixel = 3; pixel < kW * kH; ++pixel) EXPECT_EQ(w(m, pixel), 0.0f);
}

TEST(SyntheticMasks, NamesMissingFromTheManifestStillHash) {
    ScratchDir dir;
    // The manifest lacks C, and a second file has no manifest at all.
    const std::string partial = writeSynthetic(dir.file("partial.exr"), twoRankLayer("CryptoObject"),
                                               layerMetadata("CryptoObject", manifestOf({"A", "B"})));
    Evaluated e = evaluate(partial, {crypto({"C"}), crypto({"A", "C"})});
    EXPECT_TRUE(e.warnings.empty()) << e.warnings[0];
    EXPECT_FLOAT_EQ(e.weights[0].samples[0], 0.15f);
    EXPECT_FLOAT_EQ(e.weights[1].samples[1], 1.0f);

    const std::string bare =
        writeSynthetic(dir.file("bare.exr"), twoRankLayer("CryptoObject"), layerMetadata("CryptoObject", ""));
    e = evaluate(bare, {crypto({"B"}), crypto({"B*"})});
    EXPECT_FLOAT_EQ(e.weights[0].samples[0], 0.3f);
    EXPECT_EQ(e.weights[1].samples[0], 0.0f);  // wildcards need a manifest
    ASSERT_EQ(e.warnings.size(), 2u);          // "B*", and the missing manifest (tests/test_cryptomatte.cpp)
    EXPECT_NE(e.warnings[1].find(bare + ": decal 'd1': mask.cryptomatte.names[0]: 'B*' matches nothing in "
                                 "CryptoObject (the layer has no manifest, so wildcards have no names to match)"),
              std::string::npos)
        << e.warnings[1];
}

TEST(SyntheticMasks, SidecarManifestRelativeToTheExr) {
    ScratchDir dir;
    std::filesystem::create_directories(dir.file("shot"));
    std::ofstream(dir.file("shot/manifest.json")) << manifestOf({"A", "B", "C", "D"});
    // The specification's example writes "./manifest.json".
    for (const char* sidecar : {"manifest.json", "./manifest.json"}) {
        auto meta = layerMetadata("CryptoObject", "");
        meta["cryptomatte/0a1b2c3/manif_file"] = sidecar;
        const std::string path = writeSynthetic(dir.file("shot/c.exr"), twoRankLayer("CryptoObject"), meta);
        const Evaluated e = evaluate(path, {crypto({"[AB]"})});
        EXPECT_TRUE(e.warnings.empty()) << sidecar << ": " << e.warnings.front();
        EXPECT_FLOAT_EQ(e.weights[0].samples[0], 0.8f) << sidecar;
    }
}

TEST(SyntheticMasks, IdPassRoundsAndWarnsAboutFractions) {
    ScratchDir dir;
    const std::string path =
        writeSynthetic(dir.file("ids.exr"), {{"id", Imf::FLOAT, {1, 2, 3, 2.0001f, 1.98f, 0, 7, 2.5f}}}, {});
    const Evaluated e = evaluate(path, {DecalMask{{2}, {}, "", {}}, DecalMask{{}, {2, 7}, "", {}}});
    EXPECT_EQ(e.weights[0].samples, (std::vector<float>{0, 1, 0, 1, 1, 0, 0, 0}));  // 2.5 rounds away from 2
    EXPECT_EQ(e.weights[1].samples, (std::vector<float>{1, 0, 1, 0, 0, 1, 0, 1}));
    ASSERT_EQ(e.warnings.size(), 1u);
    EXPECT_NE(e.warnings[0].find(path + ": channel id: holds non-integer object ids"), std::string::npos)
        << e.warnings[0];
    EXPECT_NE(e.warnings[0].find("check that the id pass is written unfiltered"), std::string::npos) << e.warnings[0];
}

TEST(SyntheticMasks, UintAndHalfIdPasses) {
    ScratchDir dir;
    const std::string uint_path = writeSynthetic(dir.file("uint.exr"), {{"id", Imf::UINT, {1, 2, 3, 4, 5, 6, 7, 8}}}, {});
    EXPECT_EQ(evaluate(uint_path, {DecalMask{{3, 8}, {}, "", {}}}).weights[0].samples,
              (std::vector<float>{0, 0, 1, 0, 0, 0, 0, 1}));
    const std::string half_path =
        writeSynthetic(dir.file("half.exr"), {{"id", Imf::HALF, {1, 2, 3, 4, 5, 6, 7, 2048}}}, {});
    EXPECT_EQ(evaluate(half_path, {DecalMask{{7, 2048}, {}, "", {}}}).weights[0].samples,
              (std::vector<float>{0, 0, 0, 0, 0, 0, 1, 1}));
}

// ---- errors ---------------------------------------------------------------------------------

// Runs evaluate() expecting Error(Input) whose message contains every needle.
void expectMaskError(const std::string& path, const std::vector<DecalMask>& masks,
                     const std::vector<std::string>& needles) {
    try {
        evaluate(path, masks);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_EQ(e.kind(), ErrorKind::Input) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        for (const std::string& needle : needles) EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    }
}

TEST(MaskErrors, HalfCryptomatteIdsAreRefused) {
    ScratchDir dir;
    const std::string path = writeSynthetic(dir.file("half.exr"), twoRankLayer("CryptoObject", Imf::HALF),
                                            layerMetadata("CryptoObject", manifestOf({"A"})));
    expectMaskError(path, {crypto({"A"})}, {path, "channel CryptoObject00.r", "HALF cannot hold Cryptomatte ids"});
}

TEST(MaskErrors, UnsupportedHashIsRefused) {
    ScratchDir dir;
    auto meta = layerMetadata("CryptoObject", manifestOf({"A"}));
    meta["cryptomatte/0a1b2c3/hash"] = "md5";
    const std::string path = writeSynthetic(dir.file("md5.exr"), twoRankLayer("CryptoObject"), meta);
    expectMaskError(path, {crypto({"A"})}, {path, "cryptomatte/0a1b2c3/hash: unsupported hash 'md5'"});
}

TEST(MaskErrors, LayerWithoutChannelsOrMetadata) {
    ScratchDir dir;
    const std::string no_meta = writeSynthetic(dir.file("nometa.exr"), twoRankLayer("CryptoObject"), {});
    expectMaskError(no_meta, {crypto({"A"})}, {no_meta, "unknown Cryptomatte layer 'CryptoObject'", "no Cryptomatte metadata"});
    const std::string no_channels =
        writeSynthetic(dir.file("nochannels.exr"), {}, layerMetadata("CryptoObject", manifestOf({"A"})));
    expectMaskError(no_channels, {crypto({"A"})}, {no_channels, "has no channels CryptoObject00.r"});
}

TEST(MaskErrors, IdsWithoutAnObjectIdPass) {
    ScratchDir dir;
    const std::string path = writeSynthetic(dir.file("noid.exr"), {}, {});
    expectMaskError(path, {DecalMask{{}, {3}, "", {}}}, {path, "decal 'd0'", "no object-id pass", "--channel object_id="});
}

TEST(MaskErrors, IdChannelTypeMustHoldTheIds) {
    ScratchDir dir;
    const std::string half_path = writeSynthetic(dir.file("half.exr"), {{"id", Imf::HALF, std::vector<float>(8, 1)}}, {});
    expectMaskError(half_path, {DecalMask{{5000}, {}, "", {}}},
                    {half_path, "channel id", "HALF holds whole numbers exactly only up to 2048", "5000", "decal 'd0'"});
    const std::string uint_path = writeSynthetic(dir.file("uint.exr"), {{"id", Imf::UINT, std::vector<float>(8, 1)}}, {});
    expectMaskError(uint_path, {DecalMask{{}, {-1}, "", {}}}, {uint_path, "channel id", "UINT cannot hold the negative id -1"});
}

// ---- the command line ---------------------------------------------------------------------

std::vector<float> floatChannel(const ExrImage& image, const std::string& name) {
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels)
            if (c.qualified == name) {
                std::vector<float> v(c.bytes.size() / 4);
                std::memcpy(v.data(), c.bytes.data(), c.bytes.size());
                return v;
            }
    ADD_FAILURE() << "no channel " << name;
    return {};
}

TEST(MaskCli, WallOnlyDecalLeavesTheFloorBitIdentical) {
    ScratchDir dir;
    const std::string out = dir.file("out.exr");
    const auto run = test::runCli("composite " + shellQuote(test::dataPath("blender/gbuffer.exr")) + " --decals " +
                                  shellQuote(cornerScene(dir, R"({"cryptomatte": {"names": ["Wall"]}})")) +
                                  " --camera " + shellQuote(test::dataPath("blender/camera.json")) +
                                  " --device cpu -q --beauty off -o " + shellQuote(out));  // (no light passes: a warning)
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(run.output, "");
    const ExrImage input = readExr(test::dataPath("blender/gbuffer.exr"));
    const ExrImage result = readExr(out);
    const auto& object = blender().object;
    std::size_t wall_changed = 0;
    for (const char* c : {"R", "G", "B"}) {
        const std::string name = std::string("ViewLayer.DiffCol.") + c;
        const std::vector<float> a = floatChannel(input, name), b = floatChannel(result, name);
        ASSERT_EQ(a.size(), object.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (object[i] != kWall) ASSERT_EQ(std::memcmp(&a[i], &b[i], 4), 0) << name << " pixel " << i;
            else wall_changed += a[i] != b[i];
        }
    }
    EXPECT_GT(wall_changed, 500u);
}

TEST(MaskCli, NameThatMatchesNothingIsAWarningOnStderr) {
    ScratchDir dir;
    const std::string out = dir.file("out.exr");
    const auto run = test::runCli("composite " + shellQuote(test::dataPath("blender/gbuffer.exr")) + " --decals " +
                                  shellQuote(cornerScene(dir, R"({"cryptomatte": {"names": ["Wal*x"]}})")) +
                                  " --camera " + shellQuote(test::dataPath("blender/camera.json")) +
                                  " --device cpu -q -o " + shellQuote(out));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("decalcomp: warning: " + test::dataPath("blender/gbuffer.exr") +
                              ": decal 'corner_checker': mask.cryptomatte.names[0]: 'Wal*x' matches nothing in "
                              "ViewLayer.CryptoObject"),
              std::string::npos)
        << run.output;
    EXPECT_TRUE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace decalcomp
