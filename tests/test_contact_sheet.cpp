// Contact-sheet thumbnails (decalcomp/contact_sheet.hpp): filtered down in linear light, never
// enlarged, and the per-shard sheet names. The batch end to end is in test_batch_features.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "decalcomp/contact_sheet.hpp"
#include "decalcomp/textures.hpp"

namespace decalcomp {
namespace {

GBuffer albedoOnly(int w, int h, const std::function<float(int, int)>& value) {
    GBuffer g;
    g.width = w, g.height = h;
    Plane& albedo = g.planes[Attribute::Albedo];
    albedo.components = 3;
    albedo.samples.resize(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) albedo.at(std::size_t(y) * w + x, c) = value(x, y);
    return g;
}

// A one-pixel checker of 0 and 1 halved: every thumbnail pixel is the linear mean 0.5, sRGB-encoded
// (188); averaging the encoded values instead would give 128.
TEST(ContactSheet, ThumbnailsAreFilteredInLinearLight) {
    const GBuffer g = albedoOnly(512, 256, [](int x, int y) { return float((x + y) % 2); });
    const Thumbnail t = makeThumbnail(g, 256);
    ASSERT_EQ(t.width, 256);
    ASSERT_EQ(t.height, 128);
    const int expected = int(linearToSrgb(0.5f) * 255.0f + 0.5f);
    int worst = 0;
    for (int y = 8; y < t.height - 8; ++y)
        for (int x = 8; x < t.width - 8; ++x) worst = std::max(worst, std::abs(int(t.rgb[(std::size_t(y) * t.width + x) * 3]) - expected));
    EXPECT_LE(worst, 2) << "linear mean " << expected;
}

// Small frames keep their size; NaN (a background sample) shows black.
TEST(ContactSheet, SmallFramesAreNotEnlargedAndNaNIsBlack) {
    const GBuffer g = albedoOnly(40, 30, [](int x, int) { return x == 0 ? std::nanf("") : 1.0f; });
    const Thumbnail t = makeThumbnail(g, 256);
    ASSERT_EQ(t.width, 40);
    ASSERT_EQ(t.height, 30);
    EXPECT_EQ(t.rgb[0], 0);
    EXPECT_EQ(t.rgb[3], 255);
}

TEST(ContactSheet, EachShardWritesItsOwnSheet) {
    EXPECT_EQ(contactSheetPath("out/seq.png", 1, 1), "out/seq.png");
    EXPECT_EQ(contactSheetPath("out/seq.png", 3, 8), "out/seq.shard-3-of-8.png");
}

}  // namespace
}  // namespace decalcomp
