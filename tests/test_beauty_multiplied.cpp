// Undivided light end to end (issue 14, item 1): the generator writes Arnold's and RenderMan's
// diffuse light AOVs multiplied by the albedo; `composite` with an albedo decal must give
// beauty' = beauty * A'/A and light' = light * A'/A per channel on the pixels the decal changed,
// and leave every channel of every other pixel, and the alpha everywhere, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>

#include "decalcomp/exr_file.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::shellQuote;

struct Naming {
    std::string name;
    std::vector<std::string> beauty, albedo, direct, indirect;  // R, G, B channels
    std::string alpha;
};
void PrintTo(const Naming& n, std::ostream* os) { *os << n.name; }  // gtest's names

std::vector<std::string> rgb(const std::string& pass, const std::string& components) {
    std::vector<std::string> out;
    for (char c : components) out.push_back(pass.empty() ? std::string(1, c) : pass + "." + c);
    return out;
}

const Naming kArnold{"arnold", rgb("", "RGB"), rgb("diffuse_albedo", "RGB"), rgb("diffuse_direct", "RGB"),
                     rgb("diffuse_indirect", "RGB"), "A"};
const Naming kRenderMan{"renderman", rgb("Ci", "rgb"), rgb("albedo", "rgb"), rgb("directDiffuse", "rgb"),
                        rgb("indirectDiffuse", "rgb"), "a"};

float sample(const ExrImage& image, const std::string& name, std::size_t i) {
    float v;
    std::memcpy(&v, test::channel(image, name).bytes.data() + i * 4, 4);
    return v;
}

bool sameBits(const ExrChannel& a, const ExrChannel& b, std::size_t i, std::size_t pixels) {
    const std::size_t size = a.bytes.size() / pixels;
    return std::memcmp(a.bytes.data() + i * size, b.bytes.data() + i * size, size) == 0;
}

class BeautyMultiplied : public ::testing::TestWithParam<Naming> {};

TEST_P(BeautyMultiplied, BeautyAndLightFollowTheAlbedoRatio) {
    const Naming& n = GetParam();
    test::ScratchDir dir;
    const std::string in = dir.file("in.exr"), camera = dir.file("cam.json"), out = dir.file("out.exr");
    const auto gen = test::runGenerator("--width 120 --height 80 --light-passes --naming " + n.name, in, camera);
    ASSERT_EQ(gen.exit_code, 0) << gen.output;
    const std::string scene = test::writeStaticScene(dir.path());
    const auto run = test::runCli("composite " + shellQuote(in) + " --decals " + shellQuote(scene) + " --camera " +
                                  shellQuote(camera) + " --device cpu --beauty on -o " + shellQuote(out));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("light multiplied by colour"), std::string::npos) << run.output;

    const ExrImage before = readExr(in), after = readExr(out);
    const std::size_t pixels = std::size_t(before.parts[0].width) * before.parts[0].height;
    std::size_t changed = 0, unchanged = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
        ASSERT_TRUE(sameBits(test::channel(before, n.alpha), test::channel(after, n.alpha), i, pixels)) << i;
        bool albedo_changed = false;
        for (const std::string& a : n.albedo)
            albedo_changed = albedo_changed || !sameBits(test::channel(before, a), test::channel(after, a), i, pixels);
        if (!albedo_changed) {  // every channel as it was
            ++unchanged;
            for (std::size_t c = 0; c < before.parts[0].channels.size(); ++c)
                ASSERT_TRUE(sameBits(before.parts[0].channels[c], after.parts[0].channels[c], i, pixels))
                    << before.parts[0].channels[c].name << " pixel " << i;
            continue;
        }
        ++changed;
        for (int c = 0; c < 3; ++c) {
            const double a0 = sample(before, n.albedo[c], i), a1 = sample(after, n.albedo[c], i);
            const double ratio = a0 > 0 ? a1 / a0 : 1.0;  // an albedo of 0 keeps its light (docs/profiles.md)
            // A few float roundings of the values (the kernel sums the terms' changes into the beauty).
            auto expectScaled = [&](const std::string& name) {
                const double v0 = sample(before, name, i), expected = v0 * ratio;
                EXPECT_NEAR(sample(after, name, i), expected, 1e-6 * std::max(1.0, std::abs(expected)))
                    << name << " pixel " << i;
            };
            expectScaled(n.beauty[c]);
            expectScaled(n.direct[c]);
            expectScaled(n.indirect[c]);
        }
    }
    RecordProperty("changed_pixels", std::to_string(changed));
    std::cout << n.name << ": " << changed << " pixels rebuilt, " << unchanged << " untouched\n";
    EXPECT_GT(changed, 200u);
    EXPECT_GT(unchanged, 200u);
}

INSTANTIATE_TEST_SUITE_P(Renderer, BeautyMultiplied, ::testing::Values(kArnold, kRenderMan),
                         [](const auto& param) { return param.param.name; });

}  // namespace
}  // namespace decalcomp
