// decalcomp-gbuffer-gen end to end: runs the generator, reads its files back through decalcomp's
// own EXR reader and channel mapping, and checks layouts, sample types and that every depth
// convention agrees with the position pass and the camera sidecar.
#include <gtest/gtest.h>

#include <OpenEXR/ImfCompression.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "decalcomp/camera.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/header_camera.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::qualifiedNames;
using test::ScratchDir;

test::CommandResult runGen(const std::string& arguments) {
    return test::runCommand(test::shellQuote(DECALCOMP_GEN) + " " + arguments);
}

// Runs the generator into `dir` and reads the EXR back; fails the test if it does not exit 0.
ExrImage generate(const ScratchDir& dir, const std::string& name, const std::string& arguments) {
    const std::string exr = dir.file(name + ".exr");
    const test::CommandResult r =
        runGen(arguments + " -o " + test::shellQuote(exr) + " --camera " + test::shellQuote(dir.file(name + ".json")));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return readExr(exr);
}

const ExrChannel* findChannel(const ExrImage& image, const std::string& qualified) {
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& channel : part.channels)
            if (channel.qualified == qualified) return &channel;
    return nullptr;
}

void expectChannels(const ExrImage& image, const std::map<std::string, SampleType>& expected) {
    EXPECT_EQ(qualifiedNames(image).size(), expected.size());
    for (const auto& [name, type] : expected) {
        const ExrChannel* channel = findChannel(image, name);
        ASSERT_NE(channel, nullptr) << "missing channel " << name;
        EXPECT_EQ(int(channel->type), int(type)) << name;
    }
}

GBuffer load(const ExrImage& image, const MappingOptions& options = {}) {
    return extractGBuffer(image, mapChannels(image, options));
}

glm::dvec3 positionAt(const GBuffer& g, std::size_t i) {
    const Plane& p = g.planes.at(Attribute::Position);
    return {p.at(i, 0), p.at(i, 1), p.at(i, 2)};
}

glm::dvec3 cameraSpace(const Camera& camera, const glm::dvec3& world) {
    return glm::dvec3(camera.world_to_camera * glm::dvec4(world, 1.0));
}

bool isForeground(const GBuffer& g, std::size_t i) { return g.planes.at(Attribute::ObjectId).at(i, 0) > 0.5f; }

constexpr SampleType F = SampleType::Float, H = SampleType::Half, U = SampleType::Uint;

std::map<std::string, SampleType> blenderChannels(const std::string& layer, SampleType colour, bool depth = true,
                                                  bool position = true) {
    std::map<std::string, SampleType> m;
    for (const char* c : {"R", "G", "B", "A"}) m[layer + ".Combined." + c] = colour;
    if (depth) m[layer + ".Depth.Z"] = F;
    for (const char* c : {"R", "G", "B"}) m[layer + ".DiffCol." + c] = colour;
    for (const char* c : {"X", "Y", "Z"}) m[layer + ".Normal." + c] = colour;
    if (position)
        for (const char* c : {"X", "Y", "Z"}) m[layer + ".Position." + c] = F;
    m[layer + ".IndexOB.X"] = F;
    return m;
}

std::map<std::string, SampleType> genericChannels(SampleType colour, bool multipart) {
    std::map<std::string, SampleType> m;
    for (const char* c : {"R", "G", "B", "A"}) m[multipart ? std::string("rgba.") + c : std::string(c)] = colour;
    m[multipart ? "depth.Z" : "Z"] = F;
    for (const char* c : {"R", "G", "B"}) m[std::string("albedo.") + c] = colour;
    for (const char* c : {"X", "Y", "Z"}) m[std::string("N.") + c] = colour;
    for (const char* c : {"X", "Y", "Z"}) m[std::string("P.") + c] = F;
    m[multipart ? "id.V" : "id"] = U;
    m[multipart ? "roughness.V" : "roughness"] = colour;
    m[multipart ? "metallic.V" : "metallic"] = colour;
    return m;
}

// ---- layouts and types ----

TEST(GbufferGen, BlenderNamingDefaultLayout) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "--naming blender");
    ASSERT_EQ(image.parts.size(), 1u);
    EXPECT_EQ(image.parts[0].width, 320);
    EXPECT_EQ(image.parts[0].height, 240);
    EXPECT_EQ(image.parts[0].header.compression(), Imf::ZIP_COMPRESSION);
    expectChannels(image, blenderChannels("ViewLayer", F));

    const ChannelMapping mapping = mapChannels(image, {});
    EXPECT_EQ(mapping.profile, "blender");
    for (Attribute a : {Attribute::Depth, Attribute::Albedo, Attribute::Normal, Attribute::Position, Attribute::ObjectId})
        ASSERT_EQ(mapping.attributes.count(a), 1u) << attributeName(a);
    EXPECT_EQ(mapping.depth_convention, DepthConvention::Planar);

    // The demo scene's four objects are all in view, and so is some background.
    const GBuffer g = extractGBuffer(image, mapping);
    std::set<int> ids;
    for (std::size_t i = 0; i < g.pixelCount(); ++i) ids.insert(int(g.planes.at(Attribute::ObjectId).at(i, 0)));
    EXPECT_EQ(ids, (std::set<int>{1, 2, 3, 4}));  // the wall fills the view above the floor: no background

    const Camera camera = loadCameraJson(dir.file("a.json"));
    EXPECT_FALSE(camera.isOrthographic());
}

TEST(GbufferGen, BlenderNamingCustomLayerAndHalf) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "--naming blender --layer Main.Layer --half");
    expectChannels(image, blenderChannels("Main.Layer", H));
    MappingOptions options;
    options.layer = "Main.Layer";
    const GBuffer g = load(image, options);
    EXPECT_TRUE(g.has(Attribute::Albedo));
    EXPECT_TRUE(g.has(Attribute::Depth));
}

TEST(GbufferGen, GenericNamingLayout) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "--naming generic");
    ASSERT_EQ(image.parts.size(), 1u);
    expectChannels(image, genericChannels(F, false));

    const ChannelMapping mapping = mapChannels(image, {});
    EXPECT_EQ(mapping.profile, "generic");
    for (Attribute a : {Attribute::Depth, Attribute::Albedo, Attribute::Normal, Attribute::Position,
                        Attribute::ObjectId, Attribute::Roughness, Attribute::Metallic})
        EXPECT_EQ(mapping.attributes.count(a), 1u) << attributeName(a);

    const GBuffer g = extractGBuffer(image, mapping);
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        const float id = g.planes.at(Attribute::ObjectId).at(i, 0);
        ASSERT_EQ(id, std::round(id));
        ASSERT_GE(id, 0.0f);
        ASSERT_LE(id, 4.0f);
    }
}

TEST(GbufferGen, GenericNamingHalf) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "--naming generic --half");
    expectChannels(image, genericChannels(H, false));
}

TEST(GbufferGen, MultipartBlender) {
    ScratchDir dir;
    const ExrImage multi = generate(dir, "m", "--naming blender --multipart --half");
    const ExrImage single = generate(dir, "s", "--naming blender --half");
    ASSERT_EQ(multi.parts.size(), 6u);
    std::set<std::string> part_names;
    for (const ExrPart& part : multi.parts) {
        ASSERT_TRUE(part.header.hasName());
        part_names.insert(part.header.name());
        for (const ExrChannel& channel : part.channels) {
            EXPECT_EQ(channel.name.find('.'), std::string::npos) << channel.name;  // no prefix inside parts
            EXPECT_EQ(channel.qualified, part.header.name() + "." + channel.name);
        }
    }
    EXPECT_EQ(part_names, (std::set<std::string>{"ViewLayer.Combined", "ViewLayer.Depth", "ViewLayer.DiffCol",
                                                 "ViewLayer.Normal", "ViewLayer.Position", "ViewLayer.IndexOB"}));
    expectChannels(multi, blenderChannels("ViewLayer", H));

    // Same samples either way.
    const GBuffer a = load(multi), b = load(single);
    ASSERT_EQ(a.planes.size(), b.planes.size());
    for (const auto& [attribute, plane] : a.planes) {
        const std::vector<float>& other = b.planes.at(attribute).samples;
        ASSERT_EQ(plane.samples.size(), other.size());
        EXPECT_EQ(std::memcmp(plane.samples.data(), other.data(), other.size() * sizeof(float)), 0)
            << attributeName(attribute);
    }
}

TEST(GbufferGen, MultipartGeneric) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "m", "--naming generic --multipart");
    ASSERT_EQ(image.parts.size(), 8u);
    expectChannels(image, genericChannels(F, true));
    const ChannelMapping mapping = mapChannels(image, {});
    EXPECT_EQ(mapping.profile, "generic");
    EXPECT_EQ(mapping.attributes.size(), 7u);
}

TEST(GbufferGen, CompressionOption) {
    ScratchDir dir;
    const std::map<std::string, Imf::Compression> cases = {
        {"zip", Imf::ZIP_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION}, {"none", Imf::NO_COMPRESSION}};
    for (const auto& [name, compression] : cases) {
        const ExrImage image = generate(dir, name, "--compression " + name + " --multipart");
        for (const ExrPart& part : image.parts) EXPECT_EQ(part.header.compression(), compression) << name;
    }
    EXPECT_GT(fs::file_size(dir.file("none.exr")), fs::file_size(dir.file("zip.exr")));
}

// ---- depth conventions against the position pass and the camera ----

TEST(GbufferGen, PlanarDepthMatchesCameraSpacePosition) {
    ScratchDir dir;
    const GBuffer g = load(generate(dir, "a", "--depth planar"));  // demo scene
    const Camera camera = loadCameraJson(dir.file("a.json"));
    const Plane& depth = g.planes.at(Attribute::Depth);
    std::size_t floor_pixels = 0;
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        if (!isForeground(g, i)) {
            EXPECT_GE(depth.at(i, 0), 1e10f) << "background pixel " << i;
            continue;
        }
        const glm::dvec3 p = positionAt(g, i);
        ASSERT_NEAR(depth.at(i, 0), -cameraSpace(camera, p).z, 1e-4) << "pixel " << i;
        if (g.planes.at(Attribute::ObjectId).at(i, 0) == 1.0f) {
            ++floor_pixels;
            ASSERT_NEAR(p.z, 0.0, 1e-5) << "floor pixel " << i;
        }
    }
    EXPECT_GT(floor_pixels, 10000u);
}

TEST(GbufferGen, PositionLiesOnEachPixelsRay) {
    ScratchDir dir;
    const GBuffer g = load(generate(dir, "a", "--width 200 --height 120"));
    const Camera camera = loadCameraJson(dir.file("a.json"));
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = std::size_t(y) * g.width + x;
            if (!isForeground(g, i)) continue;
            const glm::dvec4 clip = camera.projection * glm::dvec4(cameraSpace(camera, positionAt(g, i)), 1.0);
            const double px = (clip.x / clip.w + 1.0) * 0.5 * g.width, py = (1.0 - clip.y / clip.w) * 0.5 * g.height;
            ASSERT_NEAR(px, x + 0.5, 1e-3) << x << "," << y;
            ASSERT_NEAR(py, y + 0.5, 1e-3) << x << "," << y;
        }
}

TEST(GbufferGen, RadialDepthIsCameraDistance) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "--naming generic --depth radial");
    MappingOptions options;
    options.depth_convention = DepthConvention::Radial;
    const GBuffer g = load(image, options);
    const Camera camera = loadCameraJson(dir.file("a.json"));
    const Plane& depth = g.planes.at(Attribute::Depth);
    std::size_t checked = 0;
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        if (!isForeground(g, i)) continue;
        const glm::dvec3 c = cameraSpace(camera, positionAt(g, i));
        ASSERT_NEAR(depth.at(i, 0), glm::length(c), 1e-4) << "pixel " << i;
        ASSERT_GT(depth.at(i, 0), -c.z - 1e-4);  // radial >= planar
        ++checked;
    }
    EXPECT_GT(checked, 20000u);
}

// The demo view has no background (floor and wall are infinite planes); random scene 2 seen by the
// generator's random-scene camera has some (with libstdc++'s distributions), so that case checks
// the background value too.
void checkNdcDepth(bool reversed, const std::string& scene, bool expect_background) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "--depth ndc " + scene + (reversed ? " --reversed-z" : ""));
    const ExrChannel* channel = findChannel(image, "ViewLayer.Depth.Z");
    ASSERT_NE(channel, nullptr);
    EXPECT_EQ(channel->type, SampleType::Float);
    const GBuffer g = load(image);
    const Camera camera = loadCameraJson(dir.file("a.json"));
    const Plane& depth = g.planes.at(Attribute::Depth);
    std::size_t background = 0;
    for (std::size_t i = 0; i < g.pixelCount(); ++i) {
        if (!isForeground(g, i)) {
            ++background;
            ASSERT_EQ(depth.at(i, 0), reversed ? 0.0f : 1.0f) << "pixel " << i;
            continue;
        }
        const glm::dvec4 clip = camera.projection * glm::dvec4(cameraSpace(camera, positionAt(g, i)), 1.0);
        const double d = (clip.z / clip.w + 1.0) * 0.5;
        ASSERT_NEAR(depth.at(i, 0), reversed ? 1.0 - d : d, 1e-5) << "pixel " << i;
        ASSERT_GT(depth.at(i, 0), 0.0f);
        ASSERT_LT(depth.at(i, 0), 1.0f);
    }
    if (expect_background) {
        EXPECT_GT(background, 0u);
    }
}

TEST(GbufferGen, NdcDepthMatchesProjection) { checkNdcDepth(false, "--scene demo", false); }
TEST(GbufferGen, ReversedNdcDepthMatchesProjection) { checkNdcDepth(true, "--scene demo", false); }
TEST(GbufferGen, NdcDepthBackground) { checkNdcDepth(false, "--scene random --seed 2", true); }
TEST(GbufferGen, ReversedNdcDepthBackground) { checkNdcDepth(true, "--scene random --seed 2", true); }

TEST(GbufferGen, PositionConventionHasNoDepthPass) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "--depth position --scene random --seed 2");  // has background
    expectChannels(image, blenderChannels("ViewLayer", F, /*depth=*/false));
    const ChannelMapping mapping = mapChannels(image, {});
    EXPECT_EQ(mapping.depth_convention, DepthConvention::Position);
    const GBuffer g = extractGBuffer(image, mapping);
    std::size_t background = 0;
    for (std::size_t i = 0; i < g.pixelCount(); ++i)
        if (!isForeground(g, i)) {
            ++background;
            ASSERT_TRUE(std::isnan(positionAt(g, i).x)) << "pixel " << i;
        }
    EXPECT_GT(background, 0u);
}

TEST(GbufferGen, NoPositionOption) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "--no-position --half");
    expectChannels(image, blenderChannels("ViewLayer", H, true, /*position=*/false));
    EXPECT_NE(runGen("--no-position --depth position -o " + test::shellQuote(dir.file("b.exr"))).exit_code, 0);
}

// ---- cameras ----

void expectMatrixNear(const glm::dmat4& a, const glm::dmat4& b, double tolerance, const char* what) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[c][r], b[c][r], tolerance) << what << " [" << r << "][" << c << "]";
}

TEST(GbufferGen, HeaderCameraRoundTripsToJsonCamera) {
    ScratchDir dir;
    for (const char* scene : {"--scene demo", "--scene random --seed 5"}) {
        const ExrImage image = generate(dir, "a", std::string(scene) + " --header-camera --multipart --width 300 --height 200");
        const Camera json = loadCameraJson(dir.file("a.json"));
        for (const ExrPart& part : image.parts) {
            const std::optional<Camera> header = cameraFromExrHeader(part.header, image.path);
            ASSERT_TRUE(header.has_value());
            expectMatrixNear(header->world_to_camera, json.world_to_camera, 1e-5, "world_to_camera");
            expectMatrixNear(header->projection, json.projection, 1e-5, "projection");
        }
    }
}

TEST(GbufferGen, NoHeaderCameraByDefault) {
    ScratchDir dir;
    const ExrImage image = generate(dir, "a", "");
    EXPECT_FALSE(cameraFromExrHeader(image.parts[0].header, image.path).has_value());
}

TEST(GbufferGen, CameraSidecarDefaultsBesideTheExr) {
    ScratchDir dir;
    fs::create_directories(dir.path() / "out");
    const test::CommandResult r =
        runGen("--width 64 --height 48 -o " + test::shellQuote(dir.file("out/frame.0001.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string sidecar = dir.file("out/frame.0001.camera.json");
    ASSERT_TRUE(fs::exists(sidecar));
    std::ifstream in(sidecar);
    const nlohmann::json doc = nlohmann::json::parse(in);
    EXPECT_EQ(doc.at("resolution"), nlohmann::json::array({64, 48}));
    const Camera camera = loadCameraJson(sidecar);
    EXPECT_NEAR(camera.projection[1][1] / camera.projection[0][0], 64.0 / 48.0, 1e-12);  // aspect
    const ExrImage image = readExr(dir.file("out/frame.0001.exr"));
    EXPECT_EQ(image.parts[0].width, 64);
    EXPECT_EQ(image.parts[0].height, 48);
}

// ---- scenes ----

TEST(GbufferGen, RandomSceneIsDeterministicPerSeed) {
    ScratchDir dir;
    const GBuffer a = load(generate(dir, "a", "--scene random --seed 7 --width 160 --height 120"));
    const GBuffer b = load(generate(dir, "b", "--scene random --seed 7 --width 160 --height 120"));
    const GBuffer c = load(generate(dir, "c", "--scene random --seed 8 --width 160 --height 120"));
    const auto& da = a.planes.at(Attribute::Depth).samples;
    EXPECT_EQ(da, b.planes.at(Attribute::Depth).samples);
    EXPECT_NE(da, c.planes.at(Attribute::Depth).samples);
    std::size_t foreground = 0;
    for (std::size_t i = 0; i < a.pixelCount(); ++i) foreground += isForeground(a, i);
    EXPECT_GT(foreground, a.pixelCount() / 10);
}

// ---- errors ----

TEST(GbufferGen, UsageErrorsExitWithCode2) {
    ScratchDir dir;
    const std::string out = " -o " + test::shellQuote(dir.file("x.exr"));
    for (const char* args : {"--depth sideways", "--naming maya", "--compression lzma", "--reversed-z",
                                   "--scene demo --seed 3", "--naming generic --layer L", "--width 0",
                                   "--bogus-option"}) {
        const test::CommandResult r = runGen(args + out);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
        EXPECT_FALSE(r.output.empty()) << args;
    }
    EXPECT_EQ(runGen("--naming blender").exit_code, 2);  // -o is required
    EXPECT_FALSE(fs::exists(dir.file("x.exr")));
}

TEST(GbufferGen, UnwritableOutputExitsWithCode5AndNamesTheFile) {
    ScratchDir dir;
    const std::string target = dir.file("missing-folder/x.exr");
    const test::CommandResult r = runGen("-o " + test::shellQuote(target));
    EXPECT_EQ(r.exit_code, 5) << r.output;
    EXPECT_NE(r.output.find(target), std::string::npos) << r.output;
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

}  // namespace
}  // namespace decalcomp
