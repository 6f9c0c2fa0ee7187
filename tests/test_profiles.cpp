// Renderer profiles as data: the built-in JSON profiles, detection by score, user profile files,
// and every renderer naming of the generator read back into the same G-buffer.
#include <gtest/gtest.h>

#include <algorithm>

#include <OpenEXR/ImfStringAttribute.h>

#include <cmath>
#include <functional>
#include <fstream>
#include <set>

#include "decalcomp/camera.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/profiles.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::imageWithChannels;

using test::ScratchDir;
using test::shellQuote;
using Names = std::vector<std::string>;


Names mapped(const ExrImage& image, const ChannelMapping& mapping, Attribute attribute) {
    Names names;
    if (auto it = mapping.attributes.find(attribute); it != mapping.attributes.end())
        for (const ChannelRef& ref : it->second) names.push_back(image.parts.at(ref.part).channels.at(ref.channel).qualified);
    return names;
}

bool hasNote(const ChannelMapping& mapping, const std::string& needle) {
    for (const std::string& note : mapping.notes)
        if (note.find(needle) != std::string::npos) return true;
    return false;
}

std::string inputError(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "expected an input error";
    return {};
}

std::string writeFile(const ScratchDir& dir, const std::string& name, const std::string& text) {
    const std::string path = dir.file(name);
    std::ofstream(path) << text;
    return path;
}

// ---- the built-ins ----

TEST(Profiles, BuiltinsAreEmbeddedAndOrdered) {
    std::vector<std::string> names;
    for (const ChannelProfile& p : builtinProfiles()) {
        names.push_back(p.name);
        EXPECT_EQ(p.source, "built-in");
        EXPECT_FALSE(p.description.empty()) << p.name;
        EXPECT_TRUE(p.attributes.count(Attribute::Depth)) << p.name;
        EXPECT_TRUE(p.attributes.count(Attribute::Albedo)) << p.name;
        for (const auto& [attribute, spellings] : p.attributes)
            for (const ProfileSpelling& s : spellings) EXPECT_EQ(int(s.channels.size()), attributeComponents(attribute));
    }
    EXPECT_EQ(names, (Names{"generic", "blender", "arnold", "renderman", "unreal", "vray"}));
}

TEST(Profiles, PatternExpansion) {
    EXPECT_EQ(expandChannelPattern("{layer}.DiffCol.{R,G,B}"),
              (Names{"{layer}.DiffCol.R", "{layer}.DiffCol.G", "{layer}.DiffCol.B"}));
    EXPECT_EQ(expandChannelPattern("Z"), Names{"Z"});
    EXPECT_EQ(expandChannelPattern("uv.{U,V}"), (Names{"uv.U", "uv.V"}));
}

struct NamedFile {
    Names channels;
    std::string profile;
    std::map<Attribute, Names> expected;
};

TEST(Profiles, EachRendererNamingIsDetected) {
    const std::vector<NamedFile> cases = {
        {{"Ci.r", "Ci.g", "Ci.b", "a", "z", "albedo.r", "albedo.g", "albedo.b", "Nn.x", "Nn.y", "Nn.z", "__Pworld.x",
          "__Pworld.y", "__Pworld.z", "id"},
         "renderman",
         {{Attribute::Depth, {"z"}},
          {Attribute::Albedo, {"albedo.r", "albedo.g", "albedo.b"}},
          {Attribute::Normal, {"Nn.x", "Nn.y", "Nn.z"}},
          {Attribute::Position, {"__Pworld.x", "__Pworld.y", "__Pworld.z"}},
          {Attribute::ObjectId, {"id"}}}},
        {{"R", "G", "B", "A", "Z", "diffuse_albedo.R", "diffuse_albedo.G", "diffuse_albedo.B", "N.X", "N.Y", "N.Z",
          "P.X", "P.Y", "P.Z", "ID", "specular_roughness", "metalness"},
         "arnold",
         {{Attribute::Depth, {"Z"}},
          {Attribute::Albedo, {"diffuse_albedo.R", "diffuse_albedo.G", "diffuse_albedo.B"}},
          {Attribute::Normal, {"N.X", "N.Y", "N.Z"}},
          {Attribute::ObjectId, {"ID"}},
          {Attribute::Roughness, {"specular_roughness"}},
          {Attribute::Metallic, {"metalness"}}}},
        {{"C.R", "C.G", "C.B", "C.A", "Z", "albedo.R", "albedo.G", "albedo.B", "N.R", "N.G", "N.B", "P.R", "P.G", "P.B",
          "id"},
         "arnold",
         {{Attribute::Normal, {"N.R", "N.G", "N.B"}}, {Attribute::Position, {"P.R", "P.G", "P.B"}}}},
        {{"FinalImage.R", "FinalImage.G", "FinalImage.B", "FinalImage.A", "SceneDepthWorldUnits.R",
          "SceneDepthWorldUnits.G", "SceneDepthWorldUnits.B", "BaseColor.R", "BaseColor.G", "BaseColor.B",
          "WorldNormal.R", "WorldNormal.G", "WorldNormal.B", "Roughness.R", "Metallic.R", "CustomStencil.R"},
         "unreal",
         {{Attribute::Depth, {"SceneDepthWorldUnits.R"}},
          {Attribute::Albedo, {"BaseColor.R", "BaseColor.G", "BaseColor.B"}},
          {Attribute::Normal, {"WorldNormal.R", "WorldNormal.G", "WorldNormal.B"}},
          {Attribute::Roughness, {"Roughness.R"}},
          {Attribute::Metallic, {"Metallic.R"}},
          {Attribute::ObjectId, {"CustomStencil.R"}}}},
        {{"SceneDepth.R", "BaseColor.R", "BaseColor.G", "BaseColor.B"}, "unreal", {{Attribute::Depth, {"SceneDepth.R"}}}},
    };
    for (const NamedFile& c : cases) {
        const ExrImage image = imageWithChannels(c.channels);
        const ChannelMapping m = mapChannels(image, MappingOptions{});
        EXPECT_EQ(m.profile, c.profile) << c.channels.front();
        for (const auto& [attribute, names] : c.expected)
            EXPECT_EQ(mapped(image, m, attribute), names) << c.profile << " " << attributeName(attribute);
        ASSERT_FALSE(m.candidates.empty());
        EXPECT_EQ(m.candidates.front().name, c.profile) << "candidates are sorted best first";
        EXPECT_TRUE(hasNote(m, "profile " + c.profile + " (auto-detected, score")) << c.profile;
        EXPECT_TRUE(hasNote(m, "other profiles: ")) << c.profile;
    }
}

TEST(Profiles, RenderManCameraSpaceNormalsAreFlagged) {
    const ExrImage image = imageWithChannels({"z", "albedo.r", "albedo.g", "albedo.b", "Nn.x", "Nn.y", "Nn.z"});
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "renderman");
    EXPECT_EQ(m.normals.space, NormalSpace::Camera);
    EXPECT_TRUE(hasNote(m, "normal: camera space"));

    const ExrImage world = imageWithChannels({"z", "albedo.r", "albedo.g", "albedo.b", "__Nworld.x", "__Nworld.y",
                                              "__Nworld.z", "Nn.x", "Nn.y", "Nn.z"});
    const ChannelMapping w = mapChannels(world, MappingOptions{});
    EXPECT_EQ(mapped(world, w, Attribute::Normal), (Names{"__Nworld.x", "__Nworld.y", "__Nworld.z"}));
    EXPECT_EQ(w.normals.space, NormalSpace::World);
}

TEST(Profiles, HeaderRulesAddToTheScore) {
    // The same names, once with a RenderMan software header: the rule tips the balance.
    ExrImage image = imageWithChannels({"Z", "albedo.R", "albedo.G", "albedo.B"});
    EXPECT_EQ(mapChannels(image, MappingOptions{}).profile, "generic") << "ties go to generic";
    image.parts[0].header.insert("software", Imf::StringAttribute("RenderMan 25.2"));
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "renderman");
    ASSERT_FALSE(m.candidates.empty());
    const auto& reasons = m.candidates.front().reasons;
    EXPECT_NE(std::find(reasons.begin(), reasons.end(), "header software = *RenderMan*"), reasons.end());
}

TEST(Profiles, BlenderHeaderAndLayerNotes) {
    ExrImage image = imageWithChannels({"Shot.Combined.R", "Shot.Depth.Z", "Shot.DiffCol.R", "Shot.DiffCol.G",
                                        "Shot.DiffCol.B"});
    image.parts[0].header.insert("BlenderMultiChannel", Imf::StringAttribute("Blender V2.55.1 and newer"));
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "blender");
    EXPECT_EQ(m.layer, "Shot");
    EXPECT_DOUBLE_EQ(m.candidates.front().score, 4 + 4 + 1 + 1);  // depth, albedo, two detect rules
    EXPECT_TRUE(hasNote(m, "blender layer 'Shot'"));
    EXPECT_TRUE(hasNote(m, "header BlenderMultiChannel"));
}

TEST(Profiles, ForcingAProfile) {
    const ExrImage image = imageWithChannels({"Z", "albedo.R", "albedo.G", "albedo.B", "N.R", "N.G", "N.B"});
    MappingOptions generic;
    generic.profile = "generic";
    const ChannelMapping g = mapChannels(image, generic);
    EXPECT_EQ(g.profile, "generic");
    EXPECT_FALSE(g.attributes.count(Attribute::Normal)) << "N.R is not a generic spelling";
    EXPECT_TRUE(hasNote(g, "profile generic (requested)"));
    MappingOptions arnold;
    arnold.profile = "arnold";
    EXPECT_EQ(mapped(image, mapChannels(image, arnold), Attribute::Normal), (Names{"N.R", "N.G", "N.B"}));
}

// ---- user profiles ----

constexpr const char* kStudioProfile = R"({
  "name": "studio",
  "description": "An in-house renderer: <layer>/beauty_depth, <layer>/diffuse_rgb",
  "detect": [{"header": "studio:renderer", "value": "tiger*", "weight": 3}],
  "depth_convention": "radial",
  "attributes": {
    "depth": ["{layer}/beauty_depth"],
    "albedo": ["{layer}/diffuse_rgb.{red,green,blue}"],
    "normal": [{"channels": ["{layer}/nrm.x", "{layer}/nrm.y", "{layer}/nrm.z"], "space": "camera"}]
  }
})";

TEST(Profiles, UserProfileFileIsDetectedAndExplained) {
    ScratchDir dir;
    const std::string file = writeFile(dir, "studio.json", kStudioProfile);
    ExrImage image = imageWithChannels({"main/beauty_depth", "main/diffuse_rgb.red", "main/diffuse_rgb.green",
                                        "main/diffuse_rgb.blue", "main/nrm.x", "main/nrm.y", "main/nrm.z"});
    image.parts[0].header.insert("studio:renderer", Imf::StringAttribute("tiger 2.1"));
    MappingOptions options;
    options.profile_files = {file};
    const ChannelMapping m = mapChannels(image, options);
    EXPECT_EQ(m.profile, "studio");
    EXPECT_EQ(m.layer, "main");
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"main/beauty_depth"});
    EXPECT_EQ(mapped(image, m, Attribute::Albedo),
              (Names{"main/diffuse_rgb.red", "main/diffuse_rgb.green", "main/diffuse_rgb.blue"}));
    EXPECT_EQ(m.normals.space, NormalSpace::Camera);
    EXPECT_EQ(m.depth_convention, DepthConvention::Radial) << "the profile's default depth convention";
    EXPECT_DOUBLE_EQ(m.candidates.front().score, 4 + 4 + 2 + 3);
    EXPECT_TRUE(hasNote(m, "profile studio from " + file));
    EXPECT_TRUE(hasNote(m, "depth <- main/beauty_depth (studio)"));
    EXPECT_TRUE(hasNote(m, "depth convention: radial (profile studio's default for a depth pass)"));

    // Without the file the name is unknown.
    MappingOptions forced;
    forced.profile = "studio";
    EXPECT_NE(inputError([&] { mapChannels(image, forced); }).find("unknown channel profile 'studio'"), std::string::npos);
}

TEST(Profiles, UserProfileReplacesABuiltinOfTheSameName) {
    ScratchDir dir;
    const std::string file = writeFile(dir, "generic.json", R"({"profiles": [{"name": "generic",
        "attributes": {"depth": ["zz"], "albedo": ["col.{r,g,b}"]}}]})");
    const std::vector<ChannelProfile> set = profileSet({file});
    int generics = 0;
    for (const ChannelProfile& p : set) generics += p.name == "generic";
    EXPECT_EQ(generics, 1);
    EXPECT_EQ(set.front().name, "generic");
    EXPECT_EQ(set.front().source, file);
    const ExrImage image = imageWithChannels({"zz", "col.r", "col.g", "col.b"});
    MappingOptions options;
    options.profile_files = {file};
    const ChannelMapping m = mapChannels(image, options);
    EXPECT_EQ(m.profile, "generic");
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"zz"});
}

// A user profile written for these files wins even when a built-in finds more names: generic
// reads Z, an old diffuse pass as albedo, N, roughness and metallic here (score 12) where the
// studio's two-attribute profile scores 8, and generic's albedo would be the wrong pass.
TEST(Profiles, SmallerUserProfileThatFitsWinsOverGeneric) {
    ScratchDir dir;
    const std::string file = writeFile(dir, "paint.json", R"({"name": "paint",
        "attributes": {"depth": ["Z"], "albedo": ["paint.{R,G,B}"]}})");
    const ExrImage image = imageWithChannels({"Z", "diffuse.R", "diffuse.G", "diffuse.B", "N.X", "N.Y", "N.Z", "roughness", "metallic",
                                              "paint.R", "paint.G", "paint.B"});
    MappingOptions options;
    options.profile_files = {file};
    const ChannelMapping m = mapChannels(image, options);
    EXPECT_EQ(m.profile, "paint");
    EXPECT_EQ(mapped(image, m, Attribute::Albedo), (Names{"paint.R", "paint.G", "paint.B"}));
    ASSERT_GE(m.candidates.size(), 2u);
    const auto generic = std::find_if(m.candidates.begin(), m.candidates.end(),
                                      [](const ProfileCandidate& c) { return c.name == "generic"; });
    ASSERT_NE(generic, m.candidates.end());
    EXPECT_GT(generic->score, 8.0) << "generic scores higher, and still loses";
    EXPECT_TRUE(hasNote(m, "profile paint (auto-detected, a user profile that finds every attribute it names, score 8: "
                           "depth, albedo)"));

    // One that does not fit (its normal is missing) is scored like any other, and loses.
    const std::string partial = writeFile(dir, "partial.json", R"({"name": "partial",
        "attributes": {"depth": ["Z"], "albedo": ["paint.{R,G,B}"], "normal": ["nrm.{x,y,z}"]}})");
    options.profile_files = {partial};
    EXPECT_EQ(mapChannels(image, options).profile, "generic");
}

TEST(Profiles, BadProfileFilesNameTheFieldAndFile) {
    ScratchDir dir;
    struct Bad {
        std::string text, needle;
    };
    const std::vector<Bad> cases = {
        {"{\"name\": \"x\", ", "not valid JSON"},
        {R"({"attributes": {"depth": ["Z"]}})", ": missing 'name'"},
        {R"({"name": "auto", "attributes": {"depth": ["Z"]}})", "name: a profile needs a name other than \"auto\""},
        {R"({"name": "x", "attributes": {"albedo": ["a.{R,G}"]}})", "attributes.albedo[0]: expected 3 channel pattern(s), got 2"},
        {R"({"name": "x", "attributes": {"colour": ["a.{R,G,B}"]}})", "attributes.colour: unknown key"},
        {R"({"name": "x", "attributes": {"depth": ["{pass}.Z"]}})", "unknown placeholder '{pass}'"},
        {R"({"name": "x", "attributes": {"depth": ["{layer}.{layer}"]}})", "{layer} may appear once"},
        {R"({"name": "x", "attributes": {"depth": [7]}})", "attributes.depth[0]: expected a channel pattern"},
        {R"({"name": "x", "attributes": {"depth": ["Z"]}, "depth": "planar"})", "depth: unknown key"},
        {R"({"name": "x", "attributes": {"depth": ["Z"]}, "depth_convention": "linear"})",
         "depth_convention: expected one of: planar, radial, ndc, position (got 'linear')"},
        {R"({"name": "x", "attributes": {"depth": ["Z"]}, "detect": [{"value": "a"}]})",
         "detect[0]: expected exactly one of \"header\" and \"channel\""},
        {R"({"name": "x", "attributes": {"depth": [{"channels": "Z", "space": "camera"}]}})",
         "attributes.depth[0].space: only normal spellings have a space"},
        {R"([{"name": "ok", "attributes": {"depth": ["Z"]}}, {"name": "x"}])", "[1]: missing 'attributes'"},
    };
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const std::string file = writeFile(dir, "bad" + std::to_string(i) + ".json", cases[i].text);
        const std::string message = inputError([&] { loadProfileFile(file); });
        EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(cases[i].needle), std::string::npos) << "case " << i << ": " << message;
    }
    EXPECT_NE(inputError([&] { loadProfileFile(dir.file("absent.json")); }).find("cannot open"), std::string::npos);
}

// ---- every renderer naming of the generator reads back into the same G-buffer ----

GBuffer generatedGBuffer(const ScratchDir& dir, const std::string& naming, ChannelMapping* mapping_out = nullptr) {
    const std::string exr = dir.file(naming + ".exr");
    const auto r = test::runGenerator("--width 40 --height 30 --naming " + naming, exr, dir.file(naming + ".json"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const ExrImage image = readExr(exr);
    const ChannelMapping mapping = mapChannels(image, MappingOptions{});
    if (mapping_out) *mapping_out = mapping;
    return extractGBuffer(image, mapping);
}

TEST(Profiles, GeneratorNamingsMapToTheSameGBuffer) {
    ScratchDir dir;
    const GBuffer reference = generatedGBuffer(dir, "generic");
    const Camera camera = loadCameraJson(dir.file("generic.json"));
    const std::map<std::string, std::string> profile_of = {{"blender", "blender"}, {"arnold", "arnold"},
                                                           {"karma", "arnold"},    {"renderman", "renderman"},
                                                           {"unreal", "unreal"},   {"generic", "generic"}};
    for (const auto& [naming, profile] : profile_of) {
        ChannelMapping mapping;
        const GBuffer g = generatedGBuffer(dir, naming, &mapping);
        EXPECT_EQ(mapping.profile, profile) << naming;
        std::set<Attribute> expected = {Attribute::Depth, Attribute::Albedo, Attribute::Normal, Attribute::Position,
                                        Attribute::ObjectId};
        if (naming != "blender") expected.insert({Attribute::Roughness, Attribute::Metallic});
        std::set<Attribute> got;
        for (const auto& [attribute, plane] : g.planes) got.insert(attribute);
        EXPECT_EQ(got, expected) << naming;
        for (Attribute a : expected) {
            const Plane& want = reference.planes.at(a);
            const Plane& have = g.planes.at(a);
            ASSERT_EQ(have.samples.size(), want.samples.size()) << naming << " " << attributeName(a);
            for (std::size_t i = 0; i < g.pixelCount(); ++i)
                for (int c = 0; c < want.components; ++c) {
                    float expected_value = want.at(i, c);
                    if (a == Attribute::Normal && mapping.normals.space == NormalSpace::Camera) {  // RenderMan's Nn
                        const glm::dvec3 n(want.at(i, 0), want.at(i, 1), want.at(i, 2));
                        expected_value = float((glm::dmat3(camera.world_to_camera) * n)[c]);
                        ASSERT_NEAR(have.at(i, c), expected_value, 1e-6) << naming << " pixel " << i;
                        continue;
                    }
                    ASSERT_EQ(have.at(i, c), expected_value) << naming << " " << attributeName(a) << " pixel " << i;
                }
        }
    }
}

// ---- the command line ----

TEST(Profiles, CliProfileFileAndUnknownProfile) {
    ScratchDir dir;
    const std::string exr = dir.file("u.exr");
    ASSERT_EQ(test::runGenerator("--width 24 --height 16 --naming unreal", exr).exit_code, 0);
    const auto info = test::runCli("info " + shellQuote(exr));
    EXPECT_EQ(info.exit_code, 0) << info.output;
    for (const char* needle : {"profile: unreal", "profile scores: unreal", "depth <- SceneDepthWorldUnits.R (unreal)",
                               "channel FinalImage.R", "camera solve: perspective"})
        EXPECT_NE(info.output.find(needle), std::string::npos) << needle << "\n" << info.output;

    const std::string profile = writeFile(dir, "mine.json", R"({"name": "mine", "attributes": {
        "depth": ["SceneDepthWorldUnits.G"], "albedo": ["BaseColor.{B,G,R}"]}})");
    const auto forced = test::runCli("info " + shellQuote(exr) + " --profile-file " + shellQuote(profile) +
                                     " --profile mine");
    EXPECT_EQ(forced.exit_code, 0) << forced.output;
    EXPECT_NE(forced.output.find("depth <- SceneDepthWorldUnits.G (mine)"), std::string::npos) << forced.output;

    const auto unknown = test::runCli("info " + shellQuote(exr) + " --profile nosuch");
    EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
    EXPECT_NE(unknown.output.find("--profile nosuch: unknown profile"), std::string::npos) << unknown.output;

    const std::string broken = writeFile(dir, "broken.json", R"({"name": "b", "attributes": {"albedo": ["x"]}})");
    const auto bad = test::runCli("info " + shellQuote(exr) + " --profile-file " + shellQuote(broken));
    EXPECT_EQ(bad.exit_code, 3) << bad.output;
    EXPECT_NE(bad.output.find(broken + ": attributes.albedo[0]"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace decalcomp
