// mapChannels: renderer profiles, view layers, explicit overrides and depth conventions.
#include <gtest/gtest.h>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>

#include <cmath>
#include <filesystem>

#include "decalcomp/camera.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::imageWithChannels;

std::string channelName(const ExrImage& image, const ChannelRef& ref) {
    return image.parts.at(ref.part).channels.at(ref.channel).qualified;
}

// The qualified names mapped to an attribute, in component order ({} when unmapped).
std::vector<std::string> mapped(const ExrImage& image, const ChannelMapping& mapping, Attribute attribute) {
    std::vector<std::string> names;
    auto it = mapping.attributes.find(attribute);
    if (it != mapping.attributes.end())
        for (const ChannelRef& ref : it->second) names.push_back(channelName(image, ref));
    return names;
}

bool hasNote(const ChannelMapping& mapping, const std::string& note) {
    return std::find(mapping.notes.begin(), mapping.notes.end(), note) != mapping.notes.end();
}

std::string inputErrorMessage(const ExrImage& image, const MappingOptions& options) {
    try {
        mapChannels(image, options);
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        return e.what();
    }
    ADD_FAILURE() << "expected an input error";
    return {};
}

using Names = std::vector<std::string>;

std::vector<std::string> blenderPasses(const std::string& layer) {
    return {layer + ".Combined.R", layer + ".Combined.G", layer + ".Combined.B", layer + ".Combined.A",
            layer + ".Depth.Z",    layer + ".DiffCol.R",  layer + ".DiffCol.G",  layer + ".DiffCol.B",
            layer + ".IndexOB.X",  layer + ".Normal.X",   layer + ".Normal.Y",   layer + ".Normal.Z",
            layer + ".Position.X", layer + ".Position.Y", layer + ".Position.Z", layer + ".UV.U",
            layer + ".UV.V",       layer + ".UV.A",       layer + ".CryptoObject00.r"};
}

TEST(ChannelMapping, BlenderCustomViewLayerIsDetected) {
    const ExrImage image = imageWithChannels(blenderPasses("RenderLayer"));
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "blender");
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"RenderLayer.Depth.Z"});
    EXPECT_EQ(mapped(image, m, Attribute::Albedo),
              (Names{"RenderLayer.DiffCol.R", "RenderLayer.DiffCol.G", "RenderLayer.DiffCol.B"}));
    EXPECT_EQ(mapped(image, m, Attribute::Normal),
              (Names{"RenderLayer.Normal.X", "RenderLayer.Normal.Y", "RenderLayer.Normal.Z"}));
    EXPECT_EQ(mapped(image, m, Attribute::Position),
              (Names{"RenderLayer.Position.X", "RenderLayer.Position.Y", "RenderLayer.Position.Z"}));
    EXPECT_EQ(mapped(image, m, Attribute::ObjectId), Names{"RenderLayer.IndexOB.X"});
    EXPECT_EQ(mapped(image, m, Attribute::UV), (Names{"RenderLayer.UV.U", "RenderLayer.UV.V"}));
    EXPECT_FALSE(m.attributes.count(Attribute::Roughness));
    EXPECT_EQ(m.depth_convention, DepthConvention::Planar);
    EXPECT_TRUE(hasNote(m, "depth <- RenderLayer.Depth.Z (blender)"));
}

TEST(ChannelMapping, BlenderNewerPassNamesAndDottedLayer) {
    const ExrImage image = imageWithChannels({"Shot.v2.Depth.Z", "Shot.v2.Diffuse Color.R", "Shot.v2.Diffuse Color.G",
                                              "Shot.v2.Diffuse Color.B", "Shot.v2.Object Index.X", "Shot.v2.UV.X",
                                              "Shot.v2.UV.Y", "Shot.v2.Roughness.X"});
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "blender");
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"Shot.v2.Depth.Z"});
    EXPECT_EQ(mapped(image, m, Attribute::Albedo),
              (Names{"Shot.v2.Diffuse Color.R", "Shot.v2.Diffuse Color.G", "Shot.v2.Diffuse Color.B"}));
    EXPECT_EQ(mapped(image, m, Attribute::ObjectId), Names{"Shot.v2.Object Index.X"});
    EXPECT_EQ(mapped(image, m, Attribute::UV), (Names{"Shot.v2.UV.X", "Shot.v2.UV.Y"}));
    EXPECT_EQ(mapped(image, m, Attribute::Roughness), Names{"Shot.v2.Roughness.X"});
}

TEST(ChannelMapping, SeveralViewLayersNeedAChoice) {
    std::vector<std::string> names = blenderPasses("Background");
    for (const std::string& n : blenderPasses("Hero")) names.push_back(n);
    const ExrImage image = imageWithChannels(names);

    const std::string ambiguous = inputErrorMessage(image, MappingOptions{});
    EXPECT_NE(ambiguous.find("in.exr: "), std::string::npos) << ambiguous;
    EXPECT_NE(ambiguous.find("Background, Hero"), std::string::npos) << ambiguous;

    MappingOptions pick;
    pick.layer = "Hero";
    const ChannelMapping m = mapChannels(image, pick);
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"Hero.Depth.Z"});
    EXPECT_EQ(mapped(image, m, Attribute::Albedo), (Names{"Hero.DiffCol.R", "Hero.DiffCol.G", "Hero.DiffCol.B"}));

    MappingOptions wrong;
    wrong.layer = "Fog";
    const std::string missing = inputErrorMessage(image, wrong);
    EXPECT_NE(missing.find("'Fog' not found"), std::string::npos) << missing;
    EXPECT_NE(missing.find("Background, Hero"), std::string::npos) << missing;
}

TEST(ChannelMapping, GenericShortNames) {
    const ExrImage image = imageWithChannels({"R", "G", "B", "A", "Z", "albedo.R", "albedo.G", "albedo.B", "N.X",
                                              "N.Y", "N.Z", "P.X", "P.Y", "P.Z", "id", "uv.U", "uv.V", "roughness",
                                              "metallic"});
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "generic");
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"Z"});
    EXPECT_EQ(mapped(image, m, Attribute::Albedo), (Names{"albedo.R", "albedo.G", "albedo.B"}));
    EXPECT_EQ(mapped(image, m, Attribute::Normal), (Names{"N.X", "N.Y", "N.Z"}));
    EXPECT_EQ(mapped(image, m, Attribute::Position), (Names{"P.X", "P.Y", "P.Z"}));
    EXPECT_EQ(mapped(image, m, Attribute::ObjectId), Names{"id"});
    EXPECT_EQ(mapped(image, m, Attribute::UV), (Names{"uv.U", "uv.V"}));
    EXPECT_EQ(mapped(image, m, Attribute::Roughness), Names{"roughness"});
    EXPECT_EQ(mapped(image, m, Attribute::Metallic), Names{"metallic"});
    EXPECT_TRUE(hasNote(m, "albedo <- albedo.R, albedo.G, albedo.B (generic)"));
}

TEST(ChannelMapping, GenericAlternativeNames) {
    const ExrImage image = imageWithChannels({"depth.Z", "diffuse.R", "diffuse.G", "diffuse.B", "normal.X", "normal.Y",
                                              "normal.Z", "position.X", "position.Y", "position.Z", "objectId",
                                              "uv.X", "uv.Y", "roughness.V", "metallic.V"});
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "generic");
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"depth.Z"});
    EXPECT_EQ(mapped(image, m, Attribute::Albedo), (Names{"diffuse.R", "diffuse.G", "diffuse.B"}));
    EXPECT_EQ(mapped(image, m, Attribute::Normal), (Names{"normal.X", "normal.Y", "normal.Z"}));
    EXPECT_EQ(mapped(image, m, Attribute::Position), (Names{"position.X", "position.Y", "position.Z"}));
    EXPECT_EQ(mapped(image, m, Attribute::ObjectId), Names{"objectId"});
    EXPECT_EQ(mapped(image, m, Attribute::UV), (Names{"uv.X", "uv.Y"}));
    EXPECT_EQ(mapped(image, m, Attribute::Roughness), Names{"roughness.V"});
    EXPECT_EQ(mapped(image, m, Attribute::Metallic), Names{"metallic.V"});
}

TEST(ChannelMapping, IncompleteAttributeStaysUnmapped) {
    const ExrImage image = imageWithChannels({"Z", "albedo.R", "albedo.G", "N.X"});
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_TRUE(m.attributes.count(Attribute::Depth));
    EXPECT_FALSE(m.attributes.count(Attribute::Albedo));
    EXPECT_FALSE(m.attributes.count(Attribute::Normal));
}

TEST(ChannelMapping, RequestedProfileIsObeyed) {
    const ExrImage blender = imageWithChannels(blenderPasses("ViewLayer"));
    MappingOptions generic;
    generic.profile = "generic";
    const ChannelMapping g = mapChannels(blender, generic);
    EXPECT_EQ(g.profile, "generic");
    EXPECT_TRUE(g.attributes.empty()) << "Blender names are not generic names";

    const ExrImage plain = imageWithChannels({"Z", "albedo.R", "albedo.G", "albedo.B"});
    MappingOptions forced;
    forced.profile = "blender";
    const ChannelMapping b = mapChannels(plain, forced);
    EXPECT_EQ(b.profile, "blender");
    EXPECT_TRUE(b.attributes.empty());

    MappingOptions unknown;
    unknown.profile = "maya";
    EXPECT_NE(inputErrorMessage(plain, unknown).find("unknown channel profile 'maya'"), std::string::npos);
}

TEST(ChannelMapping, ExplicitChannelsOverrideTheProfile) {
    const ExrImage image = imageWithChannels(blenderPasses("ViewLayer"));
    MappingOptions options;
    options.explicit_channels[Attribute::Albedo] = {"ViewLayer.Combined.R", "ViewLayer.Combined.G",
                                                    "ViewLayer.Combined.B"};
    options.explicit_channels[Attribute::Roughness] = {"ViewLayer.UV.A"};
    const ChannelMapping m = mapChannels(image, options);
    EXPECT_EQ(m.profile, "blender");
    EXPECT_EQ(mapped(image, m, Attribute::Albedo),
              (Names{"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B"}));
    EXPECT_EQ(mapped(image, m, Attribute::Roughness), Names{"ViewLayer.UV.A"});
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"ViewLayer.Depth.Z"}) << "others still from the profile";
    EXPECT_TRUE(hasNote(m, "roughness <- ViewLayer.UV.A (explicit)"));
}

TEST(ChannelMapping, ExplicitChannelMustExist) {
    const ExrImage image = imageWithChannels({"Z", "albedo.R", "albedo.G", "albedo.B"});
    MappingOptions options;
    options.explicit_channels[Attribute::Albedo] = {"foo.R", "foo.G", "foo.B"};
    EXPECT_EQ(inputErrorMessage(image, options), "in.exr: --channel albedo: no channel 'foo.R'");
}

TEST(ChannelMapping, ExplicitChannelCountMustMatchTheAttribute) {
    const ExrImage image = imageWithChannels({"Z", "albedo.R", "albedo.G", "albedo.B"});
    MappingOptions options;
    options.explicit_channels[Attribute::Albedo] = {"albedo.R", "albedo.G"};
    const std::string message = inputErrorMessage(image, options);
    EXPECT_NE(message.find("--channel albedo: expected 3 channel(s), got 2"), std::string::npos) << message;
}

TEST(ChannelMapping, DepthConventionDefaultsAndOverrides) {
    const ExrImage with_depth = imageWithChannels({"Z", "P.X", "P.Y", "P.Z"});
    EXPECT_EQ(mapChannels(with_depth, MappingOptions{}).depth_convention, DepthConvention::Planar);

    const ExrImage position_only = imageWithChannels({"P.X", "P.Y", "P.Z"});
    EXPECT_EQ(mapChannels(position_only, MappingOptions{}).depth_convention, DepthConvention::Position);

    MappingOptions ndc;
    ndc.depth_convention = DepthConvention::Ndc;
    ndc.reversed_z = true;
    const ChannelMapping m = mapChannels(with_depth, ndc);
    EXPECT_EQ(m.depth_convention, DepthConvention::Ndc);
    EXPECT_TRUE(m.reversed_z);
    EXPECT_TRUE(hasNote(m, "depth convention: ndc, reversed-Z (explicit)"));
}

// Parts named after Blender passes: their bare channel names get the part name as prefix.
TEST(ChannelMapping, MultiPartFileWithLayerInPartNames) {
    test::ScratchDir dir;
    const std::string path = dir.file("parts.exr");
    const std::vector<std::pair<std::string, Names>> parts = {
        {"RenderLayer.Combined", {"R", "G", "B", "A"}},
        {"RenderLayer.Depth", {"Z"}},
        {"RenderLayer.DiffCol", {"R", "G", "B"}},
        {"RenderLayer.Normal", {"X", "Y", "Z"}}};
    {
        std::vector<Imf::Header> headers;
        for (const auto& [name, channels] : parts) {
            Imf::Header header(4, 3);
            header.setName(name);
            header.setType(Imf::SCANLINEIMAGE);
            for (const std::string& c : channels) header.channels().insert(c, Imf::Channel(Imf::HALF));
            headers.push_back(header);
        }
        // Every sample of channel c in part p holds 10 p + c, so extraction can be checked.
        Imf::MultiPartOutputFile file(path.c_str(), headers.data(), int(headers.size()));
        std::vector<std::vector<Imath::half>> values;
        for (int p = 0; p < int(parts.size()); ++p) {
            Imf::FrameBuffer fb;
            for (int c = 0; c < int(parts[p].second.size()); ++c) {
                values.emplace_back(12, Imath::half(float(10 * p + c)));
                fb.insert(parts[p].second[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(values.back().data()),
                                                         sizeof(Imath::half), 4 * sizeof(Imath::half)));
            }
            Imf::OutputPart out(file, p);
            out.setFrameBuffer(fb);
            out.writePixels(3);
        }
    }
    const ExrImage image = readExr(path);
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "blender");
    ASSERT_EQ(mapped(image, m, Attribute::Depth), Names{"RenderLayer.Depth.Z"});
    EXPECT_EQ(m.attributes.at(Attribute::Depth)[0].part, 1);
    EXPECT_EQ(mapped(image, m, Attribute::Albedo),
              (Names{"RenderLayer.DiffCol.R", "RenderLayer.DiffCol.G", "RenderLayer.DiffCol.B"}));
    EXPECT_EQ(m.attributes.at(Attribute::Albedo)[2].part, 2);
    EXPECT_EQ(mapped(image, m, Attribute::Normal),
              (Names{"RenderLayer.Normal.X", "RenderLayer.Normal.Y", "RenderLayer.Normal.Z"}));
    const GBuffer gb = extractGBuffer(image, m);
    EXPECT_EQ(gb.width, 4);
    EXPECT_EQ(gb.height, 3);
    // R, G, B were written as 20, 21, 22 (the file stores them sorted as B, G, R).
    const Plane& albedo = gb.planes.at(Attribute::Albedo);
    for (std::size_t i = 0; i < 12; ++i) {
        EXPECT_EQ(albedo.at(i, 0), 20.0f);
        EXPECT_EQ(albedo.at(i, 1), 21.0f);
        EXPECT_EQ(albedo.at(i, 2), 22.0f);
    }
}

// The real Blender 3.4 render: every pass maps, and Depth agrees with Position through the camera.
TEST(ChannelMapping, BlenderSampleFile) {
    const std::string path = test::dataPath("blender/gbuffer.exr");
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
    const ExrImage image = readExr(path);
    const ChannelMapping m = mapChannels(image, MappingOptions{});
    EXPECT_EQ(m.profile, "blender");
    EXPECT_EQ(mapped(image, m, Attribute::Depth), Names{"ViewLayer.Depth.Z"});
    EXPECT_EQ(mapped(image, m, Attribute::Albedo),
              (Names{"ViewLayer.DiffCol.R", "ViewLayer.DiffCol.G", "ViewLayer.DiffCol.B"}));
    EXPECT_EQ(mapped(image, m, Attribute::Normal),
              (Names{"ViewLayer.Normal.X", "ViewLayer.Normal.Y", "ViewLayer.Normal.Z"}));
    EXPECT_EQ(mapped(image, m, Attribute::Position),
              (Names{"ViewLayer.Position.X", "ViewLayer.Position.Y", "ViewLayer.Position.Z"}));
    EXPECT_EQ(mapped(image, m, Attribute::ObjectId), Names{"ViewLayer.IndexOB.X"});
    EXPECT_EQ(mapped(image, m, Attribute::UV), (Names{"ViewLayer.UV.U", "ViewLayer.UV.V"}));
    EXPECT_EQ(m.depth_convention, DepthConvention::Planar);

    const GBuffer gb = extractGBuffer(image, m);
    EXPECT_EQ(gb.width, 320);
    EXPECT_EQ(gb.height, 240);
    EXPECT_EQ(gb.display_width, 320);
    EXPECT_EQ(gb.origin_x, 0);

    const std::string camera_path = test::dataPath("blender/camera.json");
    if (!std::filesystem::exists(camera_path)) return;
    const Camera camera = loadCameraJson(camera_path);
    const Plane& depth = gb.planes.at(Attribute::Depth);
    const Plane& position = gb.planes.at(Attribute::Position);
    std::size_t surface = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < gb.pixelCount(); ++i) {
        if (depth.at(i, 0) >= 1e10f) continue;  // background
        const glm::dvec4 p(position.at(i, 0), position.at(i, 1), position.at(i, 2), 1.0);
        worst = std::max(worst, std::abs(-(camera.world_to_camera * p).z - double(depth.at(i, 0))));
        ++surface;
    }
    EXPECT_GT(surface, gb.pixelCount() / 2);
    EXPECT_LT(worst, 1e-4);
}

}  // namespace
}  // namespace decalcomp
