// Material attributes end to end through `decalcomp composite`: every attribute the decals change
// (albedo, normal, roughness, metallic) is written back into the input's own channels, the rest of
// the file stays bit for bit; attributes the input lacks are left out with a warning, adding no
// channel; normals keep the input's space (camera-space RenderMan normals decode to the same world
// normals as a world-space file of the same frame).
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/exr_file.hpp"
#include "io/exr_layout.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::ScratchDir;
using test::shellQuote;

const std::string kSmall = "--width 160 --height 90";

const ExrChannel& channel(const ExrImage& image, const std::string& qualified) {
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels)
            if (c.qualified == qualified) return c;
    throw std::runtime_error(image.path + ": no channel " + qualified);
}

std::size_t pixelCount(const ExrImage& image) {
    return std::size_t(image.parts.at(0).width) * std::size_t(image.parts.at(0).height);
}

float at(const ExrImage& image, const std::string& name, std::size_t i) {
    return io::sampleAsFloat(channel(image, name), i);
}

bool sameBits(const ExrImage& a, const ExrImage& b, const std::string& name, std::size_t i) {
    const ExrChannel &ca = channel(a, name), &cb = channel(b, name);
    const std::size_t size = io::sampleSize(ca.type);
    return ca.type == cb.type && std::memcmp(ca.bytes.data() + i * size, cb.bytes.data() + i * size, size) == 0;
}

bool allSameBits(const ExrImage& a, const ExrImage& b, const std::vector<std::string>& names, std::size_t i) {
    for (const std::string& n : names)
        if (!sameBits(a, b, n, i)) return false;
    return true;
}

std::size_t changedCount(const ExrImage& a, const ExrImage& b, const std::string& name) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < pixelCount(a); ++i) n += !sameBits(a, b, name, i);
    return n;
}

// "name:TYPE" for every channel of every part, in file order.
std::vector<std::string> channelList(const ExrImage& image) {
    std::vector<std::string> names;
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels)
            names.push_back(c.qualified + ":" + io::sampleTypeName(c.type) + ":" + std::to_string(c.x_sampling) +
                            "x" + std::to_string(c.y_sampling));
    return names;
}

std::vector<std::string> allChannels(const ExrImage& image) {
    std::vector<std::string> names;
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels) names.push_back(c.qualified);
    return names;
}

// The raw bytes of a single-part file's header as stored: magic and version, then every attribute
// (name, type, size, value), each byte for byte but in name order: the chunk-copying writer
// (OpenEXR's core API, issue 13) stores the part's type attribute first. The provenance record
// decalcomp adds ("decalcomp/..." attributes, tests/test_provenance.cpp) is left out.
std::string rawHeader(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t p = 8;
    auto cstring = [&]() {
        const std::size_t end = bytes.find('\0', p);
        if (end == std::string::npos) throw std::runtime_error(path + ": truncated header");
        std::string s = bytes.substr(p, end - p);
        p = end + 1;
        return s;
    };
    std::vector<std::string> attributes;
    while (true) {
        const std::size_t start = p;
        const std::string name = cstring();
        if (name.empty()) break;  // the null byte that ends the header
        cstring();                // type name
        if (p + 4 > bytes.size()) throw std::runtime_error(path + ": truncated header");
        std::int32_t size = 0;
        std::memcpy(&size, bytes.data() + p, 4);
        p += 4 + std::size_t(size);
        if (name.rfind("decalcomp/", 0) != 0) attributes.push_back(bytes.substr(start, p - start));
    }
    std::sort(attributes.begin(), attributes.end());
    std::string header = bytes.substr(0, 8);
    for (const std::string& attribute : attributes) header += attribute;
    return header;
}

void gen(const std::string& arguments, const std::string& output, const std::string& camera) {
    const auto r = test::runGenerator(arguments, output, camera);
    ASSERT_EQ(r.exit_code, 0) << r.output;
}

test::CommandResult composite(const std::string& input, const std::string& scene, const std::string& camera,
                              const std::string& output, const std::string& extra = "") {
    return test::runCli("composite " + shellQuote(input) + " --decals " + shellQuote(scene) + " --camera " +
                        shellQuote(camera) + " --device cpu -o " + shellQuote(output) + " " + extra);
}

std::string texture(const std::string& file) { return test::dataPath("sample/textures/" + file); }

void writeFile(const std::string& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
    ASSERT_TRUE(out.good()) << path;
}

// ---------------------------------------------------------------------------------------------
// 1. The sample frame with the sample scene: every material channel changes, nothing else does.

TEST(MaterialCli, SampleSceneWritesEveryMaterialChannelBack) {
    ScratchDir dir;
    const std::string input = test::dataPath("sample/gbuffer.exr"), output = dir.file("out.exr");
    const auto r = composite(input, test::dataPath("sample/scene.json"), test::dataPath("sample/camera.json"), output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << "the sample has every attribute its decals change\n"
                                                           << r.output;

    const ExrImage in = readExr(input), out = readExr(output);
    ASSERT_EQ(in.parts.size(), 1u);
    ASSERT_EQ(channelList(out), channelList(in)) << "same channels, same types";
    ASSERT_GT(rawHeader(input).size(), 200u) << "channels, windows, compression, ... were parsed";
    EXPECT_EQ(rawHeader(output), rawHeader(input)) << "the header is written back byte for byte";
    const std::size_t pixels = pixelCount(in);
    ASSERT_EQ(pixels, 640u * 360u);

    // Geometry passes are never touched.
    for (const char* name : {"Z", "id"}) EXPECT_EQ(channel(out, name).bytes, channel(in, name).bytes) << name;

    // Every material channel changes at a substantial number of pixels.
    for (const char* name : {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "roughness", "metallic"}) {
        const std::size_t changed = changedCount(in, out, name);
        EXPECT_GT(changed, 5000u) << name << " changed at only " << changed << " pixels";
    }

    const std::vector<std::string> albedo = {"albedo.R", "albedo.G", "albedo.B"}, normal = {"N.X", "N.Y", "N.Z"};
    const std::vector<std::string> everything = allChannels(in);
    std::size_t changed_normals = 0, untouched = 0, normal_only = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
        const bool albedo_same = allSameBits(in, out, albedo, i), normal_same = allSameBits(in, out, normal, i);
        if (!normal_same) {
            // Changed normals are unit length (signed world space, float channels).
            ++changed_normals;
            const glm::dvec3 n(at(out, "N.X", i), at(out, "N.Y", i), at(out, "N.Z", i));
            EXPECT_NEAR(glm::length(n), 1.0, 1e-3) << "pixel " << i;
            if (albedo_same && sameBits(in, out, "roughness", i) && sameBits(in, out, "metallic", i)) ++normal_only;
        }
        if (albedo_same && normal_same) {
            // Outside every decal: nothing at all changes (roughness and metallic included).
            ++untouched;
            for (const std::string& name : everything)
                EXPECT_TRUE(sameBits(in, out, name, i)) << name << " changed at untouched pixel " << i;
        }
    }
    EXPECT_GT(changed_normals, 5000u);
    EXPECT_GT(untouched, pixels / 2) << "most of the frame is outside every decal";
    // The floor dent changes normals only (its albedo, roughness and metallic are left alone).
    EXPECT_GT(normal_only, 2000u);

    // The puddle: roughness set to 0.05 where it covers fully, with the albedo darkened there.
    std::size_t glossy = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
        if (std::abs(at(out, "roughness", i) - 0.05f) > 1e-3f || std::abs(at(in, "roughness", i) - 0.05f) <= 1e-3f)
            continue;
        ++glossy;
        for (const std::string& c : albedo) EXPECT_LT(at(out, c, i), at(in, c, i)) << c << " at pixel " << i;
        EXPECT_EQ(at(out, "metallic", i), 0.0f) << "pixel " << i;
    }
    EXPECT_GT(glossy, 500u) << "the puddle sets roughness 0.05";
}

// ---------------------------------------------------------------------------------------------
// 2. A decal that changes roughness only, on a frame without roughness channels.

std::string roughnessOnlyScene() {
    return R"({"textures": {"splat": {"albedo": ")" + texture("splat.png") + R"("}},
  "decals": [{"name": "gloss", "kind": "box", "texture": "splat",
              "translate": [0.3, -1.6, 0.0], "rotate_deg": [0, 0, 20], "scale": [2.4, 2.4, 0.5],
              "affects": {"roughness": {"value": 0.9}}}]})";
}

TEST(MaterialCli, MissingRoughnessChannelsWarnAndAddNoChannel) {
    ScratchDir dir;
    const std::string scene = dir.file("gloss.json"), camera = dir.file("cam.json");
    writeFile(scene, roughnessOnlyScene());

    // Control: on a frame with a roughness channel, the decal does change it.
    const std::string generic = dir.file("generic.exr"), generic_out = dir.file("generic_out.exr");
    gen(kSmall + " --naming generic", generic, camera);
    const auto control = composite(generic, scene, camera, generic_out);
    ASSERT_EQ(control.exit_code, 0) << control.output;
    {
        const ExrImage in = readExr(generic), out = readExr(generic_out);
        EXPECT_GT(changedCount(in, out, "roughness"), 100u);
        for (const char* name : {"albedo.R", "N.X", "metallic"}) EXPECT_EQ(changedCount(in, out, name), 0u) << name;
        std::size_t hits = 0;
        for (std::size_t i = 0; i < pixelCount(out); ++i)
            hits += !sameBits(in, out, "roughness", i) && std::abs(at(out, "roughness", i) - 0.9f) < 1e-3f;
        EXPECT_GT(hits, 150u) << "full coverage sets the value";
    }

    // Blender naming has no roughness: exit 0, a warning naming it, the input's channels exactly.
    const std::string blender = dir.file("blender.exr"), output = dir.file("blender_out.exr");
    gen(kSmall + " --naming blender", blender, camera);
    const auto r = composite(blender, scene, camera, output);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("decalcomp: warning: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("decals change roughness but the input has no roughness channels"), std::string::npos)
        << r.output;
    const ExrImage in = readExr(blender), out = readExr(output);
    for (const std::string& name : allChannels(in))
        EXPECT_EQ(name.find("oughness"), std::string::npos) << "the generated file should lack roughness: " << name;
    EXPECT_EQ(channelList(out), channelList(in)) << "no channel is added";
    EXPECT_EQ(rawHeader(output), rawHeader(blender));
    // Nothing the decal could change exists, so every channel is as it was.
    for (const std::string& name : allChannels(in)) EXPECT_EQ(changedCount(in, out, name), 0u) << name;
}

// ---------------------------------------------------------------------------------------------
// 3. Normal spaces: camera-space (RenderMan) and world-space (generic) files of the same frame.

std::string dentScene() {
    return R"({"textures": {"dent": {"normal": ")" + texture("dent_n.png") + R"("}},
  "decals": [{"name": "floor_dent", "kind": "box", "texture": "dent",
              "translate": [-1.9, -1.2, 0.0], "rotate_deg": [0, 0, 10], "scale": [1.6, 1.6, 0.3],
              "affects": {"normal": {"factor": 1, "mode": "rnm", "strength": 2}},
              "opacity": 1.0, "filter": "mip"}]})";
}

TEST(MaterialCli, CameraSpaceNormalsMatchWorldSpaceNormals) {
    ScratchDir dir;
    const std::string scene = dir.file("dent.json"), camera = dir.file("cam.json");
    writeFile(scene, dentScene());
    const std::string generic = dir.file("generic.exr"), renderman = dir.file("renderman.exr");
    gen(kSmall + " --naming generic", generic, camera);
    gen(kSmall + " --naming renderman", renderman, dir.file("cam_rman.json"));

    const std::string generic_out = dir.file("generic_out.exr"), renderman_out = dir.file("renderman_out.exr");
    const auto g = composite(generic, scene, camera, generic_out);
    ASSERT_EQ(g.exit_code, 0) << g.output;
    const auto rm = composite(renderman, scene, camera, renderman_out);
    ASSERT_EQ(rm.exit_code, 0) << rm.output;

    const ExrImage gin = readExr(generic), gout = readExr(generic_out);
    const ExrImage rin = readExr(renderman), rout = readExr(renderman_out);
    ASSERT_EQ(pixelCount(gin), 160u * 90u);
    ASSERT_EQ(pixelCount(rin), pixelCount(gin));
    EXPECT_EQ(channelList(rout), channelList(rin));

    // n_cam = R n_world with R the rotation of world_to_camera, so n_world = R^T n_cam.
    const glm::dmat3 to_world = glm::transpose(glm::dmat3(loadCameraJson(camera).world_to_camera));
    auto worldFromCamera = [&](const ExrImage& image, std::size_t i) {
        return to_world * glm::dvec3(at(image, "Nn.x", i), at(image, "Nn.y", i), at(image, "Nn.z", i));
    };
    auto world = [&](const ExrImage& image, std::size_t i) {
        return glm::dvec3(at(image, "N.X", i), at(image, "N.Y", i), at(image, "N.Z", i));
    };

    const std::vector<std::string> generic_normal = {"N.X", "N.Y", "N.Z"}, rman_normal = {"Nn.x", "Nn.y", "Nn.z"};
    std::size_t changed = 0, far_off = 0, tilted = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < pixelCount(gin); ++i) {
        // The inputs agree (a sanity check of the decoding).
        if (glm::length(world(gin, i)) > 0.5) {
            ASSERT_LT(glm::length(worldFromCamera(rin, i) - world(gin, i)), 1e-5) << "input pixel " << i;
        }
        if (allSameBits(gin, gout, generic_normal, i)) {
            // Untouched by the dent in world space: untouched in camera space too, bit for bit.
            EXPECT_TRUE(allSameBits(rin, rout, rman_normal, i)) << "pixel " << i;
            continue;
        }
        ++changed;
        const double d = glm::length(worldFromCamera(rout, i) - world(gout, i));
        worst = std::max(worst, d);
        far_off += d > 1e-3;
        tilted += glm::length(world(gout, i) - world(gin, i)) > 0.05;  // a real tilt, not rounding
    }
    EXPECT_GT(changed, 300u) << "the dent changes normals";
    EXPECT_GT(tilted, 100u) << "the dent tilts the normals visibly";
    EXPECT_EQ(far_off, 0u) << "worst difference " << worst;
    // The other channels are left alone in both files.
    for (const char* name : {"albedo.r", "roughness", "metallic", "z"}) EXPECT_EQ(changedCount(rin, rout, name), 0u) << name;
    for (const char* name : {"albedo.R", "roughness", "metallic", "Z"}) EXPECT_EQ(changedCount(gin, gout, name), 0u) << name;

    // Forcing world space on the camera-space file is obeyed, and so changes the result.
    const std::string forced_out = dir.file("forced_out.exr");
    const auto forced = composite(renderman, scene, camera, forced_out, "--normals world");
    ASSERT_EQ(forced.exit_code, 0) << forced.output;
    const ExrImage fout = readExr(forced_out);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < pixelCount(fout); ++i) {
        if (allSameBits(fout, rout, rman_normal, i)) continue;
        const glm::dvec3 a(at(fout, "Nn.x", i), at(fout, "Nn.y", i), at(fout, "Nn.z", i));
        const glm::dvec3 b(at(rout, "Nn.x", i), at(rout, "Nn.y", i), at(rout, "Nn.z", i));
        differ += glm::length(a - b) > 1e-2;
    }
    EXPECT_GT(differ, 100u) << "--normals world on camera-space normals must change the composite";
}

}  // namespace
}  // namespace decalcomp
