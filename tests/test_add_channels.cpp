// --add-channels: material channels the input lacks are added only on request, named as the
// matched profile spells them, filled with a neutral value where no decal writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/exr_file.hpp"
#include "io/exr_layout.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::ScratchDir;
using test::channel;
using test::shellQuote;

// A Blender-named demo frame (no roughness or metallic channels) and its camera.
struct BlenderFrame {
    ScratchDir dir;
    std::string exr = dir.file("frame.exr"), camera = dir.file("frame.json");
    BlenderFrame() {
        const auto r = test::runGenerator("--width 160 --height 90 --naming blender", exr, camera);
        EXPECT_EQ(r.exit_code, 0) << r.output;
    }
    test::CommandResult composite(const std::string& output, const std::string& extra) const {
        return test::runCli("composite " + shellQuote(exr) + " --decals " + shellQuote(test::dataPath("sample/scene.json")) +
                            " --camera " + shellQuote(camera) + " --device cpu -o " + shellQuote(output) + " " + extra);
    }
};

std::vector<std::string> channelNames(const ExrImage& image) {
    std::vector<std::string> names;
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels) names.push_back(c.qualified);
    std::sort(names.begin(), names.end());
    return names;
}

TEST(AddChannels, WithoutTheFlagNothingIsAddedAndTheUserIsWarned) {
    BlenderFrame f;
    const std::string out = f.dir.file("out.exr");
    const auto r = f.composite(out, "");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("decals change roughness but the input has no roughness channels"), std::string::npos)
        << r.output;
    EXPECT_EQ(channelNames(readExr(out)), channelNames(readExr(f.exr)));
}

TEST(AddChannels, AddedChannelsHoldTheValueWhereNoDecalWritesAndTheDecalsElsewhere) {
    BlenderFrame f;
    const std::string out = f.dir.file("out.exr");
    const auto r = f.composite(out, "--add-channels roughness=0.3,metallic");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("no roughness channels"), std::string::npos) << r.output;
    const ExrImage in = readExr(f.exr), result = readExr(out);
    std::vector<std::string> expected = channelNames(in);
    expected.push_back("ViewLayer.Metallic.X");  // the blender profile's spelling, so it maps again
    expected.push_back("ViewLayer.Roughness.X");
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(channelNames(result), expected);
    const ExrChannel& roughness = channel(result, "ViewLayer.Roughness.X");
    EXPECT_EQ(roughness.type, channel(in, "ViewLayer.DiffCol.R").type);
    // The sample scene's puddle sets roughness 0.05 and the plate writes its ORM map: most pixels
    // keep the fill value, some hold the puddle's value, others lie between.
    std::size_t fill = 0, puddle = 0, other = 0;
    const std::size_t samples = roughness.bytes.size() / io::sampleSize(roughness.type);
    for (std::size_t i = 0; i < samples; ++i) {
        const float v = io::sampleAsFloat(roughness, i);
        if (v == 0.3f) ++fill;
        else if (std::abs(v - 0.05f) < 1e-3f) ++puddle;
        else ++other;
    }
    EXPECT_GT(fill, samples / 2);
    EXPECT_GT(puddle, 10u);
    EXPECT_GT(other, 10u);
    // And the file maps the added channels when read again.
    const ChannelMapping mapping = mapChannels(result, MappingOptions{});
    EXPECT_TRUE(mapping.attributes.count(Attribute::Roughness));
    EXPECT_TRUE(mapping.attributes.count(Attribute::Metallic));
}

TEST(AddChannels, AttributesTheInputHasAreNotAddedAgain) {
    ScratchDir dir;
    const std::string out = dir.file("out.exr");
    const auto r = test::runCli("composite " + shellQuote(test::dataPath("sample/gbuffer.exr")) + " --decals " +
                                shellQuote(test::dataPath("sample/scene.json")) + " --camera " +
                                shellQuote(test::dataPath("sample/camera.json")) +
                                " --device cpu --add-channels roughness -o " + shellQuote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(channelNames(readExr(out)), channelNames(readExr(test::dataPath("sample/gbuffer.exr"))));
}

// In a multi-part file names without a dot read back as "part.name": the added channels take a
// spelling of the profile that reads back as itself, so the output maps again.
TEST(AddChannels, MultiPartOutputsMapTheAddedChannelsAgain) {
    ScratchDir dir;
    const std::string exr = dir.file("parts.exr"), camera = dir.file("parts.json"), out = dir.file("out.exr");
    const auto g = test::runGenerator("--width 160 --height 90 --naming generic --multipart", exr, camera);
    ASSERT_EQ(g.exit_code, 0) << g.output;
    // drop the generator's roughness part so there is something to add
    ExrImage image = readExr(exr);
    image.parts.erase(std::remove_if(image.parts.begin(), image.parts.end(),
                                     [](const ExrPart& p) { return p.header.hasName() && p.header.name() == "roughness"; }),
                      image.parts.end());
    ASSERT_FALSE(mapChannels(image, MappingOptions{}).attributes.count(Attribute::Roughness));
    writeExrAtomic(image, exr);
    const auto r = test::runCli("composite " + shellQuote(exr) + " --decals " +
                                shellQuote(test::dataPath("sample/scene.json")) + " --camera " + shellQuote(camera) +
                                " --device cpu --add-channels roughness -o " + shellQuote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const ChannelMapping again = mapChannels(readExr(out), MappingOptions{});
    ASSERT_TRUE(again.attributes.count(Attribute::Roughness)) << "the added roughness must map when read again";
}

TEST(AddChannels, BadRequestsAreUsageErrors) {
    BlenderFrame f;
    for (const char* bad : {"normal", "roughness=abc", "glossiness"}) {
        const std::string out = f.dir.file("bad.exr");
        const auto r = f.composite(out, std::string("--add-channels ") + bad);
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.output;
        EXPECT_NE(r.output.find("--add-channels"), std::string::npos) << r.output;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
}

}  // namespace
}  // namespace decalcomp
