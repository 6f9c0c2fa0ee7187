// The preview PNG: albedo before | after and, with a normal pass, a lit row in which normal-map
// decals show (the sample's floor dent changes only normals, so only the lit row shows it).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::Png;
using test::readPng;
using test::shellQuote;

bool same(const std::uint8_t* a, const std::uint8_t* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

TEST(Preview, LitRowShowsANormalOnlyDecalTheAlbedoRowCannot) {
    test::ScratchDir dir;
    const std::string png = dir.file("preview.png");
    const auto r = test::runCli("composite " + shellQuote(test::dataPath("sample/gbuffer.exr")) + " --decals " +
                                shellQuote(test::dataPath("sample/scene.json")) + " --camera " +
                                shellQuote(test::dataPath("sample/camera.json")) + " --device cpu -o " +
                                shellQuote(dir.file("out.exr")) + " --preview " + shellQuote(png));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Png p = readPng(png);
    const int w = 640, h = 360, gap = 4;  // the sample's size; panels are separated by 4 black pixels
    ASSERT_EQ(p.width, 2 * w + gap);
    ASSERT_EQ(p.height, 2 * h + gap) << "a frame with normals gets the lit row";
    std::size_t albedo_changed = 0, lit_changed = 0, lit_only = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool albedo = !same(p.at(x, y), p.at(x + w + gap, y));
            const bool lit = !same(p.at(x, y + h + gap), p.at(x + w + gap, y + h + gap));
            albedo_changed += albedo;
            lit_changed += lit;
            lit_only += lit && !albedo;
        }
    EXPECT_GT(albedo_changed, 5000u);
    EXPECT_GE(lit_changed, albedo_changed);
    // the dent (about 1.6 x 1.6 units of floor) and the plate's rivets and seams
    EXPECT_GT(lit_only, 500u);
}

}  // namespace
}  // namespace decalcomp
