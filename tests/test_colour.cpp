// Colour management (docs/colour.md): textures in OpenColorIO colour spaces converted to the
// scene's working space, checked against a conversion computed here from the published
// chromaticities (Rec.709 / sRGB D65 and ACES AP1, Bradford adaptation) and the sRGB curve.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "decalcomp/scene.hpp"
#include "decalcomp/textures.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::ScratchDir;
using test::shellQuote;
using Matrix3 = std::array<std::array<double, 3>, 3>;
using Vector3 = std::array<double, 3>;

// ---- the hand computation: RGB -> XYZ from primaries and white, Bradford adaptation ----

Matrix3 multiply(const Matrix3& a, const Matrix3& b) {
    Matrix3 m{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) m[r][c] += a[r][k] * b[k][c];
    return m;
}

Vector3 transform3(const Matrix3& m, const Vector3& v) {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

Matrix3 inverse(const Matrix3& m) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    Matrix3 inv{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            inv[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
        }
    return inv;
}

Vector3 xyzOf(double x, double y) { return {x / y, 1.0, (1.0 - x - y) / y}; }

// Columns: the primaries' XYZ scaled so that RGB (1,1,1) is the white point.
Matrix3 rgbToXyz(const std::array<std::array<double, 2>, 3>& primaries, std::array<double, 2> white) {
    Matrix3 p{};
    for (int c = 0; c < 3; ++c) {
        const Vector3 v = xyzOf(primaries[c][0], primaries[c][1]);
        for (int r = 0; r < 3; ++r) p[r][c] = v[r];
    }
    const Vector3 scale = transform3(inverse(p), xyzOf(white[0], white[1]));
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) p[r][c] *= scale[c];
    return p;
}

Matrix3 bradford(std::array<double, 2> from, std::array<double, 2> to) {
    const Matrix3 b = {{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
    const Vector3 s = transform3(b, xyzOf(from[0], from[1])), d = transform3(b, xyzOf(to[0], to[1]));
    const Matrix3 gain = {{{d[0] / s[0], 0, 0}, {0, d[1] / s[1], 0}, {0, 0, d[2] / s[2]}}};
    return multiply(inverse(b), multiply(gain, b));
}

// Linear Rec.709 -> ACEScg.
Matrix3 rec709ToAcescg() {
    const std::array<double, 2> d65 = {0.3127, 0.3290}, aces_white = {0.32168, 0.33767};
    const Matrix3 rec709 = rgbToXyz({{{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}}}, d65);
    const Matrix3 ap1 = rgbToXyz({{{0.713, 0.293}, {0.165, 0.830}, {0.128, 0.044}}}, aces_white);
    return multiply(inverse(ap1), multiply(bradford(d65, aces_white), rec709));
}

double srgbDecode(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// ---- fixtures ----

std::string config() { return test::dataPath("ocio/config.ocio"); }

// 8-bit straight-alpha RGBA written as stored.
void writePng(const std::string& path, int w, int h, const std::vector<std::uint8_t>& rgba) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    ASSERT_TRUE(out->open(path, spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgba.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

void writeFloatExr(const std::string& path, int w, int h, const std::vector<float>& rgba) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::FLOAT);
    ASSERT_TRUE(out->open(path, spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, rgba.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

// A one-decal scene whose texture is `texture` (a JSON value), with `top` extra top-level fields.
std::string sceneText(const std::string& texture, const std::string& top = "") {
    return "{" + top + (top.empty() ? "" : ", ") + R"("decals": [{"name": "logo", "translate": [0, 0, 0], "texture": )" +
           texture + "}]}";
}

DecalScene parse(const std::string& text, const ScratchDir& dir, const std::string& ocio = config()) {
    return parseScene(text, "scene.json", dir.path().string(), SceneOptions{ocio});
}

void expectNear(const glm::vec4& got, const Vector3& rgb, double alpha, double tolerance) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], rgb[c], tolerance) << "channel " << c;
    EXPECT_NEAR(got.a, alpha, 1e-7);
}

Vector3 times(Vector3 v, double s) { return {v[0] * s, v[1] * s, v[2] * s}; }

const std::vector<std::uint8_t> kPixels = {200, 100, 30, 255, 10, 250, 128, 128};

// ---- tests ----

TEST(ColourConversion, HandComputedMatrixIsThePublishedOne) {
    // The ACES documentation's Rec.709 -> AP1 matrix, first row and diagonal.
    const Matrix3 m = rec709ToAcescg();
    EXPECT_NEAR(m[0][0], 0.6131, 1e-4);
    EXPECT_NEAR(m[0][1], 0.3395, 1e-4);
    EXPECT_NEAR(m[0][2], 0.0474, 1e-4);
    EXPECT_NEAR(m[1][1], 0.9164, 1e-4);
    EXPECT_NEAR(m[2][2], 0.8698, 1e-4);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(m[r][0] + m[r][1] + m[r][2], 1.0, 1e-9);  // white stays white
}

TEST(ColourTexture, SrgbPngIntoAcescgMatchesTheHandComputedConversion) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    const DecalScene scene = parse(sceneText(R"("logo.png")", R"("working_space": "ACEScg")"), dir);
    EXPECT_EQ(scene.working_space, "ACEScg");
    EXPECT_EQ(scene.colour_config, config());
    ASSERT_EQ(scene.textures.size(), 1u);
    const Matrix3 m = rec709ToAcescg();
    for (int i = 0; i < 2; ++i) {
        const std::uint8_t* p = &kPixels[std::size_t(i) * 4];
        const double alpha = p[3] / 255.0;
        // Decoded and converted straight, then premultiplied.
        const Vector3 linear = {srgbDecode(p[0] / 255.0), srgbDecode(p[1] / 255.0), srgbDecode(p[2] / 255.0)};
        expectNear(scene.textures[0].texels[std::size_t(i)], times(transform3(m, linear), alpha), alpha, 2e-6);
    }
}

TEST(ColourTexture, FloatExrIsLinearRec709ByDefault) {
    ScratchDir dir;
    // Premultiplied, as OpenEXR stores it: colour 0.8, 0.4, 0.1 at alpha 0.5.
    writeFloatExr(dir.file("splat.exr"), 1, 1, {0.4f, 0.2f, 0.05f, 0.5f});
    const DecalScene scene = parse(sceneText(R"("splat.exr")", R"("working_space": "ACEScg")"), dir);
    const Vector3 converted = transform3(rec709ToAcescg(), {0.8, 0.4, 0.1});
    expectNear(scene.textures[0].texels[0], times(converted, 0.5), 0.5, 2e-6);
}

TEST(ColourTexture, ColorspaceFieldOverridesTheDefault) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    // 8-bit values declared linear Rec.709: no sRGB curve, only the matrix.
    const DecalScene scene = parse(
        sceneText(R"j({"albedo": "logo.png", "colorspace": "Linear Rec.709 (sRGB)"})j", R"("working_space": "ACEScg")"),
        dir);
    const Vector3 stored = {200 / 255.0, 100 / 255.0, 30 / 255.0};
    expectNear(scene.textures[0].texels[0], transform3(rec709ToAcescg(), stored), 1.0, 2e-6);
    // The map's own field wins over its set's.
    const DecalScene own = parse(sceneText(R"({"albedo": {"file": "logo.png", "colorspace": "ACEScg"},
                                                "colorspace": "sRGB - Texture"})",
                                           R"("working_space": "ACEScg")"),
                                 dir);
    expectNear(own.textures[0].texels[0], stored, 1.0, 1e-6);
}

TEST(ColourTexture, TextureColorspacesSetTheDefaults) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    const DecalScene scene = parse(
        sceneText(R"("logo.png")", R"("working_space": "ACEScg", "texture_colorspaces": {"integer": "ACEScg"})"), dir);
    expectNear(scene.textures[0].texels[0], {200 / 255.0, 100 / 255.0, 30 / 255.0}, 1.0, 1e-6);
}

TEST(ColourTexture, WithoutAWorkingSpaceTexturesLandInLinearRec709) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    const DecalScene scene = parse(sceneText(R"({"albedo": "logo.png", "colorspace": "sRGB - Texture"})"), dir);
    EXPECT_EQ(scene.working_space, "Linear Rec.709 (sRGB)");
    const Vector3 linear = {srgbDecode(200 / 255.0), srgbDecode(100 / 255.0), srgbDecode(30 / 255.0)};
    expectNear(scene.textures[0].texels[0], linear, 1.0, 2e-6);
}

TEST(ColourTexture, ScenesThatNameNoColourSpaceKeepTheExactBuiltInDecode) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    const test::ScopedEnv ocio("OCIO", config().c_str());  // a config in the environment changes nothing
    const DecalScene scene = parse(sceneText(R"("logo.png")"), dir, "");
    EXPECT_EQ(scene.working_space, "");
    EXPECT_EQ(scene.colour_config, "");
    const Texture2D builtIn = loadTexture2D(dir.file("logo.png"));
    ASSERT_EQ(scene.textures[0].texels.size(), builtIn.texels.size());
    for (std::size_t i = 0; i < builtIn.texels.size(); ++i) EXPECT_EQ(scene.textures[0].texels[i], builtIn.texels[i]);
}

TEST(ColourTexture, DataMapsAreNeverConverted) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    // The set's colour space applies to its albedo; the normal map's values stay as stored.
    const DecalScene scene = parse(sceneText(R"({"albedo": "logo.png", "normal": "logo.png", "colorspace": "Raw"})",
                                             R"("working_space": "ACEScg")"),
                                   dir);
    ASSERT_EQ(scene.decals.size(), 1u);
    const Texture2D& normal = scene.textures.at(std::size_t(scene.decals[0].normal_texture));
    expectNear(normal.texels[0], {200 / 255.0, 100 / 255.0, 30 / 255.0}, 1.0, 1e-7);
    EXPECT_NE(scene.decals[0].normal_texture, scene.decals[0].albedo_texture);
}

TEST(ColourTexture, ConfigComesFromTheEnvironment) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    const test::ScopedEnv ocio("OCIO", config().c_str());
    const DecalScene scene = parse(sceneText(R"("logo.png")", R"("working_space": "ACEScg")"), dir, "");
    EXPECT_EQ(scene.colour_config, config());
    EXPECT_EQ(scene.working_space, "ACEScg");
}

std::string sceneError(const std::string& text, const ScratchDir& dir, const std::string& ocio = config()) {
    return test::errorMessage(ErrorKind::Input, [&] { parse(text, dir, ocio); });
}

TEST(ColourErrors, NameTheFieldAndTheFix) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    {
        const test::ScopedEnv none("OCIO", nullptr);
        EXPECT_EQ(sceneError(sceneText(R"("logo.png")", R"("working_space": "ACEScg")"), dir, ""),
                  "scene.json: working_space: colour spaces need an OpenColorIO config: give --ocio FILE or set $OCIO");
    }
    EXPECT_EQ(sceneError(sceneText(R"("logo.png")", R"("working_space": "acescg")"), dir),
              "scene.json: working_space: 'acescg' is not a colour space of " + config() + " (did you mean 'ACEScg'?)");
    EXPECT_EQ(sceneError(sceneText(R"("logo.png")", R"("working_space": "XYZ")"), dir),
              "scene.json: working_space: 'XYZ' is not a colour space of " + config() +
                  " (it has: ACEScg, Linear Rec.709 (sRGB), sRGB - Texture, Raw)");
    EXPECT_EQ(sceneError(sceneText(R"({"albedo": "logo.png", "colorspace": "sRGB-Texture"})"), dir),
              "scene.json: decals[0].texture.colorspace: 'sRGB-Texture' is not a colour space of " + config() +
                  " (did you mean 'sRGB - Texture'?)");
    EXPECT_EQ(sceneError(sceneText(R"({"orm": {"file": "logo.png", "colorspace": "Raw"}})"), dir),
              "scene.json: decals[0].texture.orm.colorspace: normal and orm maps hold data, not colour: they are "
              "never converted (leave out 'colorspace')");
    EXPECT_EQ(sceneError(sceneText(R"({"albedo": {"path": "logo.png"}})"), dir),
              "scene.json: decals[0].texture.albedo.path: unknown key (supported: file, colorspace)");
    EXPECT_EQ(sceneError(sceneText(R"("logo.png")", R"("texture_colorspaces": {"int": "Raw"})"), dir),
              "scene.json: texture_colorspaces.int: unknown key (supported: integer, float)");
    const std::string missing = dir.file("none.ocio");
    EXPECT_EQ(sceneError(sceneText(R"("logo.png")", R"("working_space": "ACEScg")"), dir, missing),
              missing + ": cannot open the OpenColorIO config: no such file");
    std::ofstream(dir.file("broken.ocio")) << "ocio_profile_version: 2\ncolorspaces: [oops\n";
    const std::string broken =
        sceneError(sceneText(R"("logo.png")", R"("working_space": "ACEScg")"), dir, dir.file("broken.ocio"));
    EXPECT_EQ(broken.rfind(dir.file("broken.ocio") + ": cannot use the OpenColorIO config: ", 0), 0u) << broken;
    EXPECT_EQ(broken.find('\n'), std::string::npos) << broken;
}

TEST(ColourErrors, ATextureWithoutASpaceTheConfigCanNameSaysWhatToGive) {
    ScratchDir dir;
    writePng(dir.file("logo.png"), 2, 1, kPixels);
    // A config of ACEScg alone: no sRGB texture space under any of the usual names.
    std::ofstream(dir.file("aces.ocio")) << "ocio_profile_version: 2\nroles: {default: ACEScg, scene_linear: ACEScg}\n"
                                            "colorspaces:\n  - !<ColorSpace> {name: ACEScg}\n";
    EXPECT_EQ(sceneError(sceneText(R"("logo.png")", R"("working_space": "ACEScg")"), dir, dir.file("aces.ocio")),
              "scene.json: decals[0].texture: '" + dir.file("logo.png") +
                  "': no colour space known for an integer texture (" + dir.file("aces.ocio") +
                  " names none of the usual ones): give its 'colorspace', or the scene's texture_colorspaces.integer");
    // Naming the texture's space is the fix.
    const DecalScene fixed = parse(sceneText(R"({"albedo": "logo.png", "colorspace": "ACEScg"})",
                                             R"("working_space": "ACEScg")"),
                                   dir, dir.file("aces.ocio"));
    expectNear(fixed.textures[0].texels[0], {200 / 255.0, 100 / 255.0, 30 / 255.0}, 1.0, 1e-6);
}

// ---- end to end: the CLI composites an sRGB texture into an ACEScg frame ----

struct AlbedoPlane {
    int width = 0, height = 0;
    std::vector<float> rgb;
};

AlbedoPlane readAlbedo(const std::string& path) {
    AlbedoPlane plane;
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return plane;
    const OIIO::ImageSpec& spec = in->spec();
    plane.width = spec.width;
    plane.height = spec.height;
    std::vector<float> all(std::size_t(spec.width) * spec.height * spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()));
    std::array<int, 3> index{-1, -1, -1};
    for (int c = 0; c < spec.nchannels; ++c)
        for (int k = 0; k < 3; ++k)
            if (spec.channelnames[std::size_t(c)] == std::string("albedo.") + "RGB"[k]) index[std::size_t(k)] = c;
    for (int k : index) EXPECT_GE(k, 0) << path << " has no albedo.R/G/B";
    plane.rgb.resize(std::size_t(spec.width) * spec.height * 3);
    for (std::size_t p = 0; p < std::size_t(spec.width) * spec.height; ++p)
        for (int k = 0; k < 3; ++k) plane.rgb[p * 3 + k] = all[p * spec.nchannels + std::size_t(index[std::size_t(k)])];
    return plane;
}

TEST(ColourComposite, SrgbTextureIntoAnAcescgFrameMatchesTheHandComputedConversion) {
    ScratchDir dir;
    std::vector<std::uint8_t> uniform;
    for (int i = 0; i < 16; ++i) uniform.insert(uniform.end(), {200, 100, 30, 255});
    writePng(dir.file("paint.png"), 4, 4, uniform);
    // On the sample's floor in front of the sphere, opaque: covered pixels take the texture.
    const std::string decal = R"("decals": [{"name": "paint", "texture": "paint.png", "translate": [0.3, -1.6, 0],
                                              "scale": [1.6, 1.6, 0.5], "filter": "nearest"}])";
    std::ofstream(dir.file("rec709.json")) << "{" << decal << "}";
    std::ofstream(dir.file("acescg.json")) << R"({"working_space": "ACEScg", )" << decal << "}";
    const std::string input = test::dataPath("sample/gbuffer.exr"), camera = test::dataPath("sample/camera.json");
    auto composite = [&](const std::string& scene, const std::string& out, const std::string& extra) {
        return test::runCli("composite " + shellQuote(input) + " --camera " + shellQuote(camera) + " --decals " +
                            shellQuote(dir.file(scene)) + " --device cpu -q -o " + shellQuote(dir.file(out)) + " " +
                            extra);
    };
    const auto builtIn = composite("rec709.json", "rec709.exr", "");
    ASSERT_EQ(builtIn.exit_code, 0) << builtIn.output;
    const auto managed = composite("acescg.json", "acescg.exr", "--ocio " + shellQuote(config()));
    ASSERT_EQ(managed.exit_code, 0) << managed.output;

    const AlbedoPlane before = readAlbedo(input), rec709 = readAlbedo(dir.file("rec709.exr")),
                      acescg = readAlbedo(dir.file("acescg.exr"));
    ASSERT_EQ(rec709.rgb.size(), acescg.rgb.size());
    const Vector3 linear = {srgbDecode(200 / 255.0), srgbDecode(100 / 255.0), srgbDecode(30 / 255.0)};
    const Vector3 expected = transform3(rec709ToAcescg(), linear);
    std::size_t covered = 0, changed = 0;
    for (std::size_t p = 0; p * 3 < rec709.rgb.size(); ++p) {
        bool differs = false, full = true;
        for (int k = 0; k < 3; ++k) {
            differs |= rec709.rgb[p * 3 + k] != before.rgb[p * 3 + k];
            full &= std::abs(rec709.rgb[p * 3 + k] - linear[std::size_t(k)]) <= 1e-3 * linear[std::size_t(k)];
        }
        changed += differs;
        if (!differs || !full) continue;
        ++covered;
        // Half-float channels: a relative tolerance of half's precision.
        for (int k = 0; k < 3; ++k)
            ASSERT_NEAR(acescg.rgb[p * 3 + k], expected[std::size_t(k)], 1e-3 * expected[std::size_t(k)])
                << "pixel " << p << " channel " << k;
    }
    EXPECT_GT(covered, 1000u);
    EXPECT_GT(covered, changed / 2);  // the decal is mostly interior
}

TEST(ColourComposite, BatchTakesTheConfigAsCompositeDoes) {
    ScratchDir dir;
    std::ofstream(dir.file("acescg.json")) << R"({"working_space": "ACEScg", "decals": [{"name": "scorch",
        "texture": ")" << test::dataPath("sample/textures/scorch.png") << R"(", "translate": [0.3, -1.6, 0],
        "scale": [1.6, 1.6, 0.5]}]})";
    std::filesystem::copy_file(test::dataPath("sample/gbuffer.exr"), dir.file("in.0001.exr"));
    const std::string common = " --camera " + shellQuote(test::dataPath("sample/camera.json")) + " --decals " +
                               shellQuote(dir.file("acescg.json")) + " --device cpu -q --ocio " + shellQuote(config());
    const auto batch = test::runCli("batch " + shellQuote(dir.file("in.####.exr")) + " -o " +
                                    shellQuote(dir.file("out.####.exr")) + common);
    ASSERT_EQ(batch.exit_code, 0) << batch.output;
    const auto single = test::runCli("composite " + shellQuote(dir.file("in.0001.exr")) + " -o " +
                                     shellQuote(dir.file("single.exr")) + common);
    ASSERT_EQ(single.exit_code, 0) << single.output;
    EXPECT_EQ(readAlbedo(dir.file("out.0001.exr")).rgb, readAlbedo(dir.file("single.exr")).rgb);
    EXPECT_NE(readAlbedo(dir.file("out.0001.exr")).rgb, readAlbedo(dir.file("in.0001.exr")).rgb);
    const test::ScopedEnv none("OCIO", nullptr);
    const auto refused = test::runCli("batch " + shellQuote(dir.file("in.####.exr")) + " -o " +
                                      shellQuote(dir.file("again.####.exr")) + " --camera " +
                                      shellQuote(test::dataPath("sample/camera.json")) + " --decals " +
                                      shellQuote(dir.file("acescg.json")) + " --device cpu -q");
    EXPECT_EQ(refused.exit_code, 3) << refused.output;
    EXPECT_NE(refused.output.find("working_space: colour spaces need an OpenColorIO config"), std::string::npos)
        << refused.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("again.0001.exr")));
}

TEST(ColourComposite, BadColourSpaceFailsBeforeAnyOutput) {
    ScratchDir dir;
    std::ofstream(dir.file("bad.json")) << R"({"working_space": "ACES", "decals": [{"translate": [0, 0, 0],
                                               "affects": {"roughness": {"value": 0.5}}}]})";
    const auto r = test::runCli("composite " + shellQuote(test::dataPath("sample/gbuffer.exr")) + " --camera " +
                                shellQuote(test::dataPath("sample/camera.json")) + " --decals " +
                                shellQuote(dir.file("bad.json")) + " --ocio " + shellQuote(config()) +
                                " --device cpu -q -o " + shellQuote(dir.file("out.exr")));
    EXPECT_EQ(r.exit_code, 3) << r.output;  // a bad input
    EXPECT_NE(r.output.find(dir.file("bad.json") + ": working_space: 'ACES' is not a colour space of " + config() +
                            " (did you mean 'ACEScg'?)"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(test::occurrences(r.output, "\n"), 1u) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("out.exr")));
}

}  // namespace
}  // namespace decalcomp
