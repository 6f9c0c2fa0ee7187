// Texture decoding: sRGB curves, straight vs premultiplied alpha, channel expansion, errors.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <vector>

#include "decalcomp/error.hpp"
#include "decalcomp/textures.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::ScratchDir;

// Writes pixels exactly as given: the hint stops OIIO's PNG writer from un-premultiplying.
// `fileType` is what the file stores when it differs from the type of `pixels`.
void writeImage(const std::string& path, int w, int h, int channels, OIIO::TypeDesc type, const void* pixels,
                const std::string& decalAlpha = "", OIIO::TypeDesc fileType = OIIO::TypeDesc::UNKNOWN) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out) << OIIO::geterror();
    OIIO::ImageSpec spec(w, h, channels, fileType == OIIO::TypeDesc::UNKNOWN ? type : fileType);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!decalAlpha.empty()) spec.attribute("decal:alpha", decalAlpha);
    ASSERT_TRUE(out->open(path, spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(type, pixels)) << out->geterror();
    ASSERT_TRUE(out->close());
}

// Independent statement of the sRGB EOTF, as the brief and decals.json spell it.
double eotf(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

void expectTexel(const glm::vec4& got, const glm::vec4& want, float tolerance = 1e-6f) {
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[c], want[c], tolerance) << "channel " << c;
}

TEST(TextureSrgb, MatchesTheExactCurve) {
    EXPECT_EQ(srgbToLinear(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgbToLinear(1.0f), 1.0f);
    EXPECT_FLOAT_EQ(srgbToLinear(0.04045f), float(0.04045 / 12.92));
    for (int i = 0; i <= 255; ++i) EXPECT_NEAR(srgbToLinear(i / 255.0f), eotf(i / 255.0), 1e-7) << i;
    EXPECT_NEAR(linearToSrgb(0.214041144f), 0.5f, 1e-6);
}

TEST(TextureSrgb, RoundTrips) {
    for (int i = 0; i <= 1000; ++i) {
        const float x = i / 1000.0f;
        EXPECT_NEAR(linearToSrgb(srgbToLinear(x)), x, 1e-6) << x;
        EXPECT_NEAR(srgbToLinear(linearToSrgb(x)), x, 1e-6) << x;
    }
}

TEST(TextureLoad, Png8IsSrgbDecodedThenPremultiplied) {
    ScratchDir dir;
    // Row 0 (top): red-ish half transparent, opaque white; row 1: transparent, grey a=64.
    const std::uint8_t px[] = {200, 100, 10, 128, 255, 255, 255, 255, 50, 60, 70, 0, 128, 128, 128, 64};
    writeImage(dir.file("t.png"), 2, 2, 4, OIIO::TypeDesc::UINT8, px);
    const Texture2D tex = loadTexture2D(dir.file("t.png"));
    ASSERT_EQ(tex.width, 2);
    ASSERT_EQ(tex.height, 2);
    ASSERT_EQ(tex.texels.size(), 4u);
    EXPECT_EQ(tex.source, dir.file("t.png"));
    const float a = 128 / 255.0f;
    expectTexel(tex.texels[0],
                {srgbToLinear(200 / 255.0f) * a, srgbToLinear(100 / 255.0f) * a, srgbToLinear(10 / 255.0f) * a, a});
    expectTexel(tex.texels[1], {1, 1, 1, 1});
    expectTexel(tex.texels[2], {0, 0, 0, 0});
    const float g = float(eotf(128 / 255.0)) * (64 / 255.0f);
    expectTexel(tex.texels[3], {g, g, g, 64 / 255.0f});
    // OIIO's own premultiply would give srgb(200*a) or similar; make sure it is not that.
    EXPECT_GT(std::abs(tex.texels[0].r - srgbToLinear(200 / 255.0f * a)), 1e-3);
}

TEST(TextureLoad, Png16UsesTheFullRange) {
    ScratchDir dir;
    const std::uint16_t px[] = {40000, 0, 65535, 30000};
    writeImage(dir.file("t16.png"), 1, 1, 4, OIIO::TypeDesc::UINT16, px);
    const Texture2D tex = loadTexture2D(dir.file("t16.png"));
    const float a = 30000 / 65535.0f;
    expectTexel(tex.texels[0], {float(eotf(40000 / 65535.0)) * a, 0, a, a});
}

TEST(TextureLoad, GreyAndGreyAlphaAndRgbExpand) {
    ScratchDir dir;
    const std::uint8_t grey[] = {0, 255, 128};
    writeImage(dir.file("g.png"), 3, 1, 1, OIIO::TypeDesc::UINT8, grey);
    const Texture2D g = loadTexture2D(dir.file("g.png"));
    const float mid = srgbToLinear(128 / 255.0f);
    expectTexel(g.texels[0], {0, 0, 0, 1});
    expectTexel(g.texels[1], {1, 1, 1, 1});
    expectTexel(g.texels[2], {mid, mid, mid, 1});

    const std::uint8_t ga[] = {128, 51};
    writeImage(dir.file("ga.png"), 1, 1, 2, OIIO::TypeDesc::UINT8, ga);
    const float a = 51 / 255.0f;
    expectTexel(loadTexture2D(dir.file("ga.png")).texels[0], {mid * a, mid * a, mid * a, a});

    const std::uint8_t rgb[] = {255, 128, 0};
    writeImage(dir.file("rgb.png"), 1, 1, 3, OIIO::TypeDesc::UINT8, rgb);
    expectTexel(loadTexture2D(dir.file("rgb.png")).texels[0], {1, mid, 0, 1});
}

TEST(TextureLoad, RowZeroIsTheTopRow) {
    ScratchDir dir;
    const std::uint8_t px[] = {255, 0};  // 1x2 grey: top white, bottom black
    writeImage(dir.file("col.png"), 1, 2, 1, OIIO::TypeDesc::UINT8, px);
    const Texture2D tex = loadTexture2D(dir.file("col.png"));
    EXPECT_EQ(tex.texels[0].r, 1.0f);
    EXPECT_EQ(tex.texels[1].r, 0.0f);
}

TEST(TextureLoad, PngPremultipliedModeSkipsTheMultiply) {
    ScratchDir dir;
    const std::uint8_t px[] = {200, 200, 200, 128};
    writeImage(dir.file("p.png"), 1, 1, 4, OIIO::TypeDesc::UINT8, px);
    const float c = srgbToLinear(200 / 255.0f);
    expectTexel(loadTexture2D(dir.file("p.png"), AlphaMode::Premultiplied).texels[0], {c, c, c, 128 / 255.0f});
}

TEST(TextureLoad, ExrIsLinearAndPremultipliedByDefault) {
    ScratchDir dir;
    const float px[] = {0.5f, 0.25f, 2.0f, 0.5f};
    writeImage(dir.file("t.exr"), 1, 1, 4, OIIO::TypeDesc::FLOAT, px);
    expectTexel(loadTexture2D(dir.file("t.exr")).texels[0], {0.5f, 0.25f, 2.0f, 0.5f});
    expectTexel(loadTexture2D(dir.file("t.exr"), AlphaMode::Straight).texels[0], {0.25f, 0.125f, 1.0f, 0.5f});
}

TEST(TextureLoad, ExrHeaderCanDeclareStraightAlpha) {
    ScratchDir dir;
    const float px[] = {0.5f, 0.25f, 1.0f, 0.5f};
    writeImage(dir.file("s.exr"), 1, 1, 4, OIIO::TypeDesc::FLOAT, px, "straight");
    expectTexel(loadTexture2D(dir.file("s.exr")).texels[0], {0.25f, 0.125f, 0.5f, 0.5f});
    // An explicit scene setting wins over the header.
    expectTexel(loadTexture2D(dir.file("s.exr"), AlphaMode::Premultiplied).texels[0], {0.5f, 0.25f, 1.0f, 0.5f});
}

TEST(TextureLoad, HalfExrRgbIsOpaqueAndLinear) {
    ScratchDir dir;
    const float values[] = {0.5f, 0.25f, 0.125f};
    writeImage(dir.file("h.exr"), 1, 1, 3, OIIO::TypeDesc::FLOAT, values, "", OIIO::TypeDesc::HALF);
    expectTexel(loadTexture2D(dir.file("h.exr")).texels[0], {0.5f, 0.25f, 0.125f, 1.0f});
}

TEST(TextureLoad, MissingFileNamesThePath) {
    ScratchDir dir;
    const std::string path = dir.file("nope.png");
    try {
        loadTexture2D(path);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

TEST(TextureLoad, UnreadableFileNamesThePath) {
    ScratchDir dir;
    const std::string path = dir.file("garbage.png");
    std::ofstream(path) << "this is not an image";
    try {
        loadTexture2D(path);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

TEST(TextureLoad, BlenderSampleDecodes) {
    const Texture2D tex = loadTexture2D(test::dataPath("blender/decal_ring.png"));
    EXPECT_EQ(tex.width, 128);
    EXPECT_EQ(tex.height, 128);
    for (const glm::vec4& t : tex.texels) {
        ASSERT_GE(t.a, 0.0f);
        ASSERT_LE(t.a, 1.0f);
        ASSERT_LE(t.r, t.a + 1e-6f);  // premultiplied: colour never exceeds alpha for LDR input
    }
}

}  // namespace
}  // namespace decalcomp
