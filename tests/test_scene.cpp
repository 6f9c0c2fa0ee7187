// Scene files: placements, defaults, ordering, texture sharing, the neutral Blender format, errors.
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <array>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "decalcomp/error.hpp"
#include "decalcomp/scene.hpp"
#include "decalcomp/textures.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::ScratchDir;
namespace fs = std::filesystem;

// A 1x1 opaque RGBA8 PNG whose red channel is `red`, so tests can tell textures apart.
void writePng(const std::string& path, std::uint8_t red) {
    fs::create_directories(fs::path(path).parent_path());
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(1, 1, 4, OIIO::TypeDesc::UINT8);
    const std::uint8_t px[] = {red, 0, 0, 255};
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    ASSERT_TRUE(out->close());
}

std::string writeScene(const ScratchDir& dir, const std::string& text, const std::string& name = "scene.json") {
    const std::string path = dir.file(name);
    fs::create_directories(fs::path(path).parent_path());
    std::ofstream(path) << text;
    return path;
}

// Builds a scene with one texture "t" (tex/t.png) and the given decals array text.
struct SceneFixture {
    ScratchDir dir;
    SceneFixture() { writePng(dir.file("tex/t.png"), 255); }
    std::string scene(const std::string& decals) {
        return writeScene(dir, R"({"textures": {"t": "tex/t.png"}, "decals": )" + decals + "}");
    }
};

// Expected matrices are written row by row as in the files.
glm::dmat4 rows(std::initializer_list<std::initializer_list<double>> r) {
    glm::dmat4 m(0.0);
    int i = 0;
    for (const auto& row : r) {
        int j = 0;
        for (double v : row) m[j++][i] = v;
        ++i;
    }
    return m;
}

void expectMatrixNear(const glm::dmat4& got, const glm::dmat4& want, double tolerance = 1e-12) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(got[c][r], want[c][r], tolerance) << "row " << r << " col " << c;
}

TEST(SceneLoad, MatrixIsRowMajorWithTranslationInTheLastColumn) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([{"name": "m", "kind": "box", "texture": "t",
        "matrix": [[2,0,0,1],[0,3,0,2],[0,0,4,3],[0,0,0,1]]}])"));
    ASSERT_EQ(s.decals.size(), 1u);
    expectMatrixNear(s.decals[0].world_matrix, rows({{2, 0, 0, 1}, {0, 3, 0, 2}, {0, 0, 4, 3}, {0, 0, 0, 1}}));
    const glm::dvec4 p = s.decals[0].world_matrix * glm::dvec4(0.5, 0.5, 0.5, 1.0);
    EXPECT_EQ(p, glm::dvec4(2.0, 3.5, 5.0, 1.0));
}

TEST(SceneLoad, DefaultsApply) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([{"texture": "t", "translate": [0,0,0]}])"));
    ASSERT_EQ(s.decals.size(), 1u);
    const Decal& d = s.decals[0];
    EXPECT_EQ(d.name, "decals[0]");
    EXPECT_EQ(d.kind, DecalKind::Box);
    EXPECT_EQ(d.opacity, 1.0f);
    EXPECT_EQ(d.filter, TextureFilter::Linear);
    EXPECT_EQ(d.albedo_texture, 0);
    expectMatrixNear(d.world_matrix, glm::dmat4(1.0));
}

TEST(SceneLoad, FieldsAreRead) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([{"name": "x", "texture": "t", "translate": [0,0,0],
        "opacity": 0.25, "filter": "nearest", "priority": -3, "_note": "ignored", "description": "ok"}])"));
    EXPECT_EQ(s.decals[0].name, "x");
    EXPECT_EQ(s.decals[0].opacity, 0.25f);
    EXPECT_EQ(s.decals[0].filter, TextureFilter::Nearest);
}

TEST(SceneLoad, TopLevelFilterAndInterpolationSetTheDefault) {
    ScratchDir dir;
    writePng(dir.file("t.png"), 9);
    const std::string a = writeScene(dir, R"({"filter": "nearest", "decals": [
        {"texture": "t.png", "scale": 1}, {"texture": "t.png", "scale": 1, "filter": "linear"}]})",
                                     "a.json");
    const DecalScene sa = loadScene(a);
    EXPECT_EQ(sa.decals[0].filter, TextureFilter::Nearest);
    EXPECT_EQ(sa.decals[1].filter, TextureFilter::Linear);
    const std::string b =
        writeScene(dir, R"({"interpolation": "closest", "decals": [{"texture": "t.png", "scale": 1}]})", "b.json");
    EXPECT_EQ(loadScene(b).decals[0].filter, TextureFilter::Nearest);
}

TEST(SceneLoad, TrsEqualsAnIndependentMatrix) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([{"texture": "t",
        "translate": [1,2,3], "rotate_deg": [0,0,90], "scale": [2,3,4]}])"));
    // Rz(90) sends +X to +Y and +Y to -X; columns are scaled by (2,3,4) first.
    expectMatrixNear(s.decals[0].world_matrix, rows({{0, -3, 0, 1}, {2, 0, 0, 2}, {0, 0, 4, 3}, {0, 0, 0, 1}}));
}

TEST(SceneLoad, EulerAnglesApplyXThenYThenZ) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([{"texture": "t", "rotate_deg": [90,0,90]}])"));
    // Rx(90): X->X, Y->Z, Z->-Y; then Rz(90): X->Y, Y->-X, Z->Z. So X->Y, Y->Z, Z->X.
    expectMatrixNear(s.decals[0].world_matrix, rows({{0, 0, 1, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 1}}));
}

TEST(SceneLoad, QuaternionMatchesEulerAndIsNormalised) {
    SceneFixture f;
    const double h = std::sqrt(0.5);
    const DecalScene s = loadScene(f.scene(fmt::format(R"([
        {{"texture": "t", "quaternion_wxyz": [{0},0,0,{0}], "translate": [1,2,3], "scale": 2}},
        {{"texture": "t", "quaternion_wxyz": [2,0,0,2], "translate": [1,2,3], "scale": [2,2,2]}},
        {{"texture": "t", "rotate_deg": [0,0,90], "translate": [1,2,3], "scale": 2}}])",
                                                       h)));
    const glm::dmat4 want = rows({{0, -2, 0, 1}, {2, 0, 0, 2}, {0, 0, 2, 3}, {0, 0, 0, 1}});
    for (const Decal& d : s.decals) expectMatrixNear(d.world_matrix, want, 1e-12);
}

TEST(SceneLoad, LookAtPointsLocalMinusZFromOriginToTarget) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([{"texture": "t",
        "origin": [0,-5,1], "target": [0,0,1], "up": [0,0,1], "size": [2,3,4]}])"));
    const glm::dmat4& m = s.decals[0].world_matrix;
    // Centre at the target; local -Z (projection direction) along +Y; local +Y along up (+Z);
    // local +X to the right as seen from the origin (+X here); lengths = size.
    expectMatrixNear(m, rows({{2, 0, 0, 0}, {0, 0, -4, 0}, {0, 3, 0, 1}, {0, 0, 0, 1}}));
    const glm::dvec3 forward = glm::normalize(glm::dvec3(m * glm::dvec4(0, 0, -1, 0)));
    EXPECT_NEAR(glm::length(forward - glm::dvec3(0, 1, 0)), 0.0, 1e-12);
}

TEST(SceneLoad, LookAtUpIsMadePerpendicular) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([{"texture": "t",
        "origin": [3,4,5], "target": [1,1,1], "up": [0,0.2,1], "size": 1}])"));
    const glm::dmat4& m = s.decals[0].world_matrix;
    const glm::dvec3 x(m[0]), y(m[1]), z(m[2]);
    EXPECT_NEAR(glm::dot(x, y), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(y, z), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(-z, glm::normalize(glm::dvec3(-2, -3, -4))), 1.0, 1e-12);
    EXPECT_GT(glm::dot(y, glm::dvec3(0, 0.2, 1)), 0.0);
    EXPECT_NEAR(glm::determinant(glm::dmat3(m)), 1.0, 1e-12);  // right-handed, not mirrored
    EXPECT_EQ(glm::dvec3(m[3]), glm::dvec3(1, 1, 1));
}

TEST(SceneLoad, PriorityOrderIsStable) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([
        {"name": "a", "texture": "t", "scale": 1, "priority": 1},
        {"name": "b", "texture": "t", "scale": 1},
        {"name": "c", "texture": "t", "scale": 1, "priority": 1},
        {"name": "d", "texture": "t", "scale": 1, "priority": 0},
        {"name": "e", "texture": "t", "scale": 1, "priority": -1}])"));
    std::vector<std::string> names;
    for (const Decal& d : s.decals) names.push_back(d.name);
    EXPECT_EQ(names, (std::vector<std::string>{"e", "b", "d", "a", "c"}));
}

TEST(SceneLoad, TexturesResolveRelativeToTheSceneAndAreShared) {
    ScratchDir dir;
    writePng(dir.file("scenes/tex/a.png"), 10);
    writePng(dir.file("scenes/tex/b.png"), 200);
    const std::string path = writeScene(dir, R"({
        "textures": {"a": {"albedo": "tex/a.png"}, "a2": "./tex/../tex/a.png", "b": "tex/b.png"},
        "decals": [{"texture": "a", "scale": 1}, {"texture": "tex/a.png", "scale": 1},
                   {"texture": "b", "scale": 1}, {"texture": "a2", "scale": 1}]})",
                                        "scenes/scene.json");
    const DecalScene s = loadScene(path);
    ASSERT_EQ(s.textures.size(), 2u);
    EXPECT_EQ(s.decals[0].albedo_texture, 0);
    EXPECT_EQ(s.decals[1].albedo_texture, 0);
    EXPECT_EQ(s.decals[2].albedo_texture, 1);
    EXPECT_EQ(s.decals[3].albedo_texture, 0);
    EXPECT_NEAR(s.textures[0].texels[0].r, srgbToLinear(10 / 255.0f), 1e-7);
    EXPECT_NEAR(s.textures[1].texels[0].r, srgbToLinear(200 / 255.0f), 1e-7);
}

TEST(SceneLoad, AbsoluteTexturePathsWork) {
    ScratchDir dir, other;
    writePng(other.file("abs.png"), 77);
    const std::string path =
        writeScene(dir, nlohmann::json{{"decals", {{{"texture", other.file("abs.png")}, {"scale", 1}}}}}.dump());
    const DecalScene s = loadScene(path);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_NEAR(s.textures[0].texels[0].r, srgbToLinear(77 / 255.0f), 1e-7);
}

TEST(SceneLoad, TextureKeyWinsOverAFileOfTheSameName) {
    ScratchDir dir;
    writePng(dir.file("a.png"), 10);
    writePng(dir.file("b.png"), 200);
    const std::string path =
        writeScene(dir, R"({"textures": {"a.png": "b.png"}, "decals": [{"texture": "a.png", "scale": 1}]})");
    EXPECT_NEAR(loadScene(path).textures[0].texels[0].r, srgbToLinear(200 / 255.0f), 1e-7);
}

TEST(SceneLoad, TextureAlphaModeIsPassedOn) {
    ScratchDir dir;
    auto out = OIIO::ImageOutput::create(dir.file("t.exr"));
    const float px[] = {0.5f, 0.5f, 0.5f, 0.5f};
    ASSERT_TRUE(out->open(dir.file("t.exr"), OIIO::ImageSpec(1, 1, 4, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px));
    out->close();
    const std::string path = writeScene(dir, R"({"textures": {"s": {"albedo": "t.exr", "alpha": "straight"}},
        "decals": [{"texture": "s", "scale": 1}, {"texture": "t.exr", "scale": 1},
                   {"texture": {"albedo": "t.exr", "alpha": "straight"}, "scale": 1}]})");
    const DecalScene s = loadScene(path);
    ASSERT_EQ(s.textures.size(), 2u);                                   // same file, different alpha modes
    EXPECT_EQ(s.decals[2].albedo_texture, s.decals[0].albedo_texture);  // inline object, same request
    EXPECT_FLOAT_EQ(s.textures[size_t(s.decals[0].albedo_texture)].texels[0].r, 0.25f);
    EXPECT_FLOAT_EQ(s.textures[size_t(s.decals[1].albedo_texture)].texels[0].r, 0.5f);
}

// A 1x1 RGBA8 PNG with the given bytes.
void writePngRgba(const std::string& path, std::array<std::uint8_t, 4> px) {
    fs::create_directories(fs::path(path).parent_path());
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(1, 1, 4, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    ASSERT_TRUE(out->close());
}

TEST(SceneLoad, TextureSetMapsAreLoadedAsDataOrColour) {
    ScratchDir dir;
    writePngRgba(dir.file("a.png"), {128, 128, 128, 255});
    writePngRgba(dir.file("n.png"), {128, 64, 255, 255});
    writePngRgba(dir.file("orm.png"), {255, 51, 0, 255});
    writePngRgba(dir.file("e.png"), {128, 0, 0, 255});
    const std::string path = writeScene(dir, R"({"textures": {
        "set": {"albedo": "a.png", "normal": "n.png", "orm": "orm.png", "emission": "e.png"},
        "dx": {"normal": "n.png", "normal_y": "down"}},
        "decals": [{"texture": "set", "scale": 1}, {"texture": "dx", "scale": 1}]})");
    const DecalScene s = loadScene(path);
    const Decal& d = s.decals[0];
    ASSERT_GE(d.normal_texture, 0);
    ASSERT_GE(d.orm_texture, 0);
    ASSERT_GE(d.emission_texture, 0);
    auto texel = [&](int index) { return s.textures[std::size_t(index)].texels[0]; };
    EXPECT_NEAR(texel(d.albedo_texture).r, srgbToLinear(128.0f / 255.0f), 1e-6);  // colour: sRGB decoded
    EXPECT_NEAR(texel(d.emission_texture).r, srgbToLinear(128.0f / 255.0f), 1e-6);
    EXPECT_NEAR(texel(d.normal_texture).g, 64.0f / 255.0f, 1e-6);  // data: as stored
    EXPECT_NEAR(texel(d.orm_texture).g, 51.0f / 255.0f, 1e-6);
    // the same file with +Y down is another texture, its green flipped
    const Decal& dx = s.decals[1];
    EXPECT_EQ(dx.albedo_texture, -1);
    ASSERT_NE(dx.normal_texture, d.normal_texture);
    EXPECT_NEAR(texel(dx.normal_texture).g, 1.0f - 64.0f / 255.0f, 1e-6);
    EXPECT_NEAR(texel(dx.normal_texture).r, 128.0f / 255.0f, 1e-6);
}

TEST(SceneLoad, AffectsSetsFactorsOpsAndValues) {
    SceneFixture f;
    const DecalScene s = loadScene(f.scene(R"([
        {"texture": "t", "scale": 1},
        {"texture": {"albedo": "tex/t.png", "normal": "tex/t.png"}, "scale": 1,
         "affects": {"albedo": 0.5, "roughness": {"factor": 2, "op": "add", "value": 0.25},
                                                 "emission": {"value": [1, 2, 3]},
                                                 "normal": {"mode": "whiteout", "strength": 1.5, "factor": 0.75}}},
        {"scale": 1, "affects": {"metallic": {"value": 1, "op": "replace"}}}])"));
    const Decal& plain = s.decals[0];
    EXPECT_EQ(plain.effects, defaultTargetEffects());  // no "affects": every map of the set, defaults
    EXPECT_EQ(plain.effect(DecalTarget::AmbientOcclusion).op, BlendOp::Multiply);
    EXPECT_EQ(plain.effect(DecalTarget::Emission).op, BlendOp::Add);
    const Decal& d = s.decals[1];
    EXPECT_FLOAT_EQ(d.effect(DecalTarget::Albedo).factor, 0.5f);
    EXPECT_EQ(d.effect(DecalTarget::Albedo).op, BlendOp::Over);
    EXPECT_FLOAT_EQ(d.effect(DecalTarget::Roughness).factor, 2.0f);
    EXPECT_EQ(d.effect(DecalTarget::Roughness).op, BlendOp::Add);
    EXPECT_FLOAT_EQ(d.effect(DecalTarget::Roughness).value->r, 0.25f);
    EXPECT_EQ(*d.effect(DecalTarget::Emission).value, glm::vec3(1, 2, 3));
    EXPECT_FLOAT_EQ(d.effect(DecalTarget::Normal).factor, 0.75f);
    EXPECT_EQ(d.normal_blend, NormalBlend::Whiteout);
    EXPECT_FLOAT_EQ(d.normal_strength, 1.5f);
    EXPECT_EQ(d.effect(DecalTarget::Metallic).factor, 0.0f);  // not listed: left alone
    EXPECT_EQ(d.effect(DecalTarget::AmbientOcclusion).factor, 0.0f);
    EXPECT_TRUE(decalAffects(d, DecalTarget::Roughness));  // a constant without a texture
    EXPECT_TRUE(decalAffects(d, DecalTarget::Normal));     // the set's normal map
    EXPECT_FALSE(decalAffects(d, DecalTarget::Emission) && d.emission_texture >= 0);  // a constant, no map
    const Decal& untextured = s.decals[2];
    EXPECT_EQ(untextured.albedo_texture, -1);
    EXPECT_TRUE(decalAffects(untextured, DecalTarget::Metallic));
    EXPECT_EQ(untextured.effect(DecalTarget::Metallic).op, BlendOp::Replace);
}

TEST(SceneLoad, EmptyDecalListIsValid) {
    ScratchDir dir;
    const DecalScene s = loadScene(writeScene(dir, R"({"decals": []})"));
    EXPECT_TRUE(s.decals.empty());
    EXPECT_TRUE(s.textures.empty());
}

TEST(SceneLoad, CommentsAreAllowed) {
    SceneFixture f;
    const std::string path = writeScene(f.dir,
                                        "{\n// a comment\n\"textures\": {\"t\": \"tex/t.png\"}, /* more */\n"
                                        "\"decals\": [{\"texture\": \"t\", \"scale\": 1}]}\n");
    EXPECT_EQ(loadScene(path).decals.size(), 1u);
}

TEST(SceneLoad, BlenderNeutralFormat) {
    const std::string path = test::dataPath("blender/decals.json");
    const DecalScene s = loadScene(path);
    ASSERT_EQ(s.decals.size(), 4u);
    ASSERT_EQ(s.textures.size(), 4u);
    nlohmann::json file;
    std::ifstream(path) >> file;
    for (size_t i = 0; i < 4; ++i) {
        const Decal& d = s.decals[i];
        const nlohmann::json& j = file["decals"][i];
        EXPECT_EQ(d.name, j["name"].get<std::string>());
        EXPECT_EQ(d.kind, DecalKind::Box);
        EXPECT_EQ(d.filter, TextureFilter::Nearest);  // "interpolation": "closest"
        EXPECT_FLOAT_EQ(d.opacity, j["opacity"].get<float>());
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) EXPECT_EQ(d.world_matrix[c][r], j["world_matrix"][r][c].get<double>());
        const Texture2D& t = s.textures.at(size_t(d.albedo_texture));
        EXPECT_EQ(t.width, 128);
        EXPECT_EQ(t.height, 128);
        EXPECT_NE(t.source.find(j["texture"].get<std::string>()), std::string::npos);
    }
    EXPECT_FLOAT_EQ(s.decals[3].opacity, 0.6f);
}

// ---- errors: each names the file and the JSON path -------------------------------------------

struct ErrorCase {
    const char* label;
    const char* json;      // whole scene text
    const char* expected;  // substring after "<file>: "
};

std::ostream& operator<<(std::ostream& os, const ErrorCase& c) { return os << c.label; }

class SceneErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(SceneErrors, NameTheJsonPath) {
    ScratchDir dir;
    writePng(dir.file("t.png"), 1);
    test::expectSceneError(writeScene(dir, GetParam().json), GetParam().expected);
}

#define D(body) "{\"decals\": [" body "]}"
#define T "\"texture\": \"t.png\""
const ErrorCase kErrorCases[] = {
    {"NotJson", "{\"decals\": [ }", "not valid JSON at line 1 column 14"},
    {"NotJsonMultiline", "{\n  \"decals\": [\n    1,\n  }\n", "not valid JSON at line 4 column 3"},
    {"Empty", "", "not valid JSON at line 1 column 1"},
    {"NotObject", "[1, 2]", "expected a JSON object"},
    {"MissingDecals", "{\"textures\": {}}", "missing 'decals'"},
    {"DecalsNotArray", "{\"decals\": {}}", "decals: expected an array"},
    {"TopLevelTypo", "{\"decal\": [], \"decals\": []}", "decal: unknown key (did you mean 'decals'?)"},
    {"DecalNotObject", D("3"), "decals[0]: expected an object"},
    {"UnsupportedKind", D("{" T ", \"scale\": 1}, {" T ", \"scale\": 1}, {\"kind\": \"spline\", \"fov_y_deg\": 40}"),
     "decals[2].kind: unsupported kind 'spline' (supported: box, volume, frustum, cube)"},
    {"FovOnBox", D("{" T ", \"scale\": 1, \"fov_y_deg\": 40}"), "decals[0].fov_y_deg: only frustum decals have this field"},
    {"FrustumFarBeforeNear", D("{\"kind\": \"frustum\", " T ", \"scale\": 1, \"near\": 2, \"far\": 1}"),
     "decals[0].far: expected a distance beyond 'near'"},
    {"AngleFadeOrder", D("{" T ", \"scale\": 1, \"fade\": {\"angle_deg\": [80, 20]}}"),
     "decals[0].fade.angle_deg: expected 0 <= start < end <= 180"},
    {"DistanceFadeOnBox", D("{" T ", \"scale\": 1, \"fade\": {\"distance\": [1, 2]}}"),
     "decals[0].fade.distance: only frustum decals have a distance fade"},
    {"OcclusionOnBox", D("{" T ", \"scale\": 1, \"occlusion\": true}"),
     "decals[0].occlusion: only frustum and cube decals have blast occlusion"},
    {"OcclusionOnVolume", D("{\"kind\": \"volume\", " T ", \"scale\": 1, \"occlusion\": {\"resolution\": 64}}"),
     "decals[0].occlusion: only frustum and cube decals have blast occlusion"},
    {"OcclusionType", D("{\"kind\": \"frustum\", " T ", \"scale\": 1, \"occlusion\": \"yes\"}"),
     "decals[0].occlusion: expected true, false or an object with resolution, bias"},
    {"OcclusionResolutionRange",
     D("{" T ", \"scale\": 1}, {\"kind\": \"frustum\", " T ", \"scale\": 1, \"occlusion\": {\"resolution\": 8}}"),
     "decals[1].occlusion.resolution: expected an integer in [16, 4096]"},
    {"OcclusionResolutionFraction", D("{\"kind\": \"cube\", " T ", \"scale\": 1, \"occlusion\": {\"resolution\": 64.5}}"),
     "decals[0].occlusion.resolution: expected an integer in [16, 4096]"},
    {"OcclusionResolutionHuge", D("{\"kind\": \"cube\", " T ", \"scale\": 1, \"occlusion\": {\"resolution\": 8192}}"),
     "decals[0].occlusion.resolution: expected an integer in [16, 4096]"},
    {"OcclusionBiasZero", D("{\"kind\": \"cube\", " T ", \"scale\": 1, \"occlusion\": {\"bias\": 0}}"),
     "decals[0].occlusion.bias: expected texels in (0, 64]"},
    {"OcclusionBiasType", D("{\"kind\": \"frustum\", " T ", \"scale\": 1, \"occlusion\": {\"bias\": \"2\"}}"),
     "decals[0].occlusion.bias: expected a number"},
    {"OcclusionUnknownKey", D("{\"kind\": \"frustum\", " T ", \"scale\": 1, \"occlusion\": {\"size\": 3}}"),
     "decals[0].occlusion.size: unknown key (supported: resolution, bias)"},
    {"VolumeWithCubeTexture", D("{\"kind\": \"volume\", \"texture\": {\"cube\": \"x.png\"}, \"scale\": 1}"),
     "decals[0].texture.cube: a volume decal needs a volume texture"},
    {"KindNotString", D("{\"kind\": 1}"), "decals[0].kind: expected a string"},
    {"UnknownKey", D("{" T ", \"scale\": 1, \"opactiy\": 1}"),
     "decals[0].opactiy: unknown key (did you mean 'opacity'?)"},
    {"LocationWithoutWorldMatrix", D("{" T ", \"location\": [0,0,0]}"), "decals[0].location: unknown key"},
    {"UnknownFilter", D("{" T ", \"scale\": 1, \"filter\": \"cubic\"}"),
     "decals[0].filter: expected one of: nearest, linear, mip (got 'cubic')"},
    {"BadFilter", D("{" T ", \"scale\": 1, \"filter\": \"cubic\"}"), "decals[0].filter: expected one of: nearest, linear, mip (got 'cubic')"},
    {"OpacityRange",
     D("{" T ", \"scale\": 1}, {" T ", \"scale\": 1}, {" T ", \"scale\": 1}, {" T ", \"scale\": 1, \"opacity\": 1.5}"),
     "decals[3].opacity: expected a number in [0, 1]"},
    {"OpacityType", D("{" T ", \"scale\": 1, \"opacity\": \"1\"}"), "decals[0].opacity: expected a number in [0, 1]"},
    {"PriorityFloat", D("{" T ", \"scale\": 1, \"priority\": 1.5}"), "decals[0].priority: expected an integer"},
    {"PriorityRange", D("{" T ", \"scale\": 1, \"priority\": 9999999999}"), "decals[0].priority: expected an integer in [-2147483648, 2147483647]"},
    {"NameType", D("{" T ", \"scale\": 1, \"name\": 3}"), "decals[0].name: expected a string"},
    {"NoTexture", D("{\"scale\": 1}"), "decals[0]: missing 'texture' (a decal needs a texture set, or constant values in 'affects')"},
    {"AffectsNotObject", D("{" T ", \"scale\": 1, \"affects\": 1}"), "decals[0].affects: expected an object"},
    {"AffectsUnknownAttribute", D("{" T ", \"scale\": 1, \"affects\": {\"albedo\": 1, \"glossiness\": 1}}"),
     "decals[0].affects.glossiness: unknown key (supported: albedo, normal, roughness, metallic, ao, emission)"},
    {"AffectsNegativeFactor", D("{" T ", \"scale\": 1, \"affects\": {\"roughness\": -0.5}}"),
     "decals[0].affects.roughness: expected a factor >= 0"},
    {"AffectsBadOp", D("{" T ", \"scale\": 1, \"affects\": {\"roughness\": {\"op\": \"screen\"}}}"),
     "decals[0].affects.roughness.op: expected one of: over, multiply, add, replace"},
    {"AffectsNormalOp", D("{" T ", \"scale\": 1, \"affects\": {\"normal\": {\"op\": \"add\"}}}"),
     "decals[0].affects.normal.op: unknown key (supported: factor, mode, strength)"},
    {"AffectsNormalMode", D("{" T ", \"scale\": 1, \"affects\": {\"normal\": {\"mode\": \"blend\"}}}"),
     "decals[0].affects.normal.mode: expected one of: rnm, udn, whiteout, replace"},
    {"AffectsNormalStrength", D("{" T ", \"scale\": 1, \"affects\": {\"normal\": {\"strength\": -1}}}"),
     "decals[0].affects.normal.strength: expected a number in [0, 100]"},
    {"AffectsScalarValueRange", D("{" T ", \"scale\": 1, \"affects\": {\"metallic\": {\"value\": 2}}}"),
     "decals[0].affects.metallic.value: expected a number in [0, 1]"},
    {"AffectsColourValueShape", D("{" T ", \"scale\": 1, \"affects\": {\"albedo\": {\"value\": [1, 0]}}}"),
     "decals[0].affects.albedo.value: expected [r, g, b] (linear) or one number"},
    {"AffectsOnlyFactorsNoTexture", D("{\"scale\": 1, \"affects\": {\"roughness\": 0.5}}"),
     "decals[0].affects.roughness: nothing to write: the texture set has no 'orm' map and there is no 'value'"},
    {"AffectsNormalWithoutMap", D("{" T ", \"scale\": 1, \"affects\": {\"albedo\": 1, \"normal\": 1}}"),
     "decals[0].affects.normal: nothing to write: the texture set has no 'normal' map"},
    {"UnknownTextureName", D("{\"texture\": \"scorch\", \"scale\": 1}"), "decals[0].texture: unknown texture 'scorch'"},
    {"TextureType", D("{\"texture\": 5, \"scale\": 1}"), "decals[0].texture: expected a texture name"},
    {"NoPlacement", D("{" T "}"), "decals[0]: missing placement"},
    {"MatrixAndTranslate", D("{" T ", \"matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], \"translate\": [0,0,0]}"),
     "decals[0]: conflicting placements 'matrix' and 'translate'"},
    {"MatrixAndWorldMatrix",
     D("{" T ", \"matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "
       "\"world_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}"),
     "decals[0]: give either 'matrix' or 'world_matrix'"},
    {"TrsAndLookAt", D("{" T ", \"scale\": 1, \"origin\": [0,0,0]}"), "conflicting placements 'scale' and 'origin'"},
    {"SingularMatrix", D("{" T ", \"scale\": 1}, {" T ", \"matrix\": [[1,0,0,0],[0,0,0,0],[0,0,1,0],[0,0,0,1]]}"),
     "decals[1].matrix: not invertible (degenerate decal)"},
    {"SingularWorldMatrix", D("{" T ", \"world_matrix\": [[1,0,0,0],[2,0,0,0],[0,0,1,0],[0,0,0,1]]}"),
     "decals[0].world_matrix: not invertible (degenerate decal)"},
    {"ProjectiveMatrix", D("{" T ", \"matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]}"),
     "decals[0].matrix: last row must be [0, 0, 0, 1]"},
    {"MatrixShape", D("{" T ", \"matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]}"),
     "decals[0].matrix: expected 4 rows of 4 numbers"},
    {"MatrixFlat", D("{" T ", \"matrix\": [1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]}"),
     "decals[0].matrix: expected 4 rows of 4 numbers"},
    {"MatrixElement", D("{" T ", \"matrix\": [[1,0,0,0],[0,1,\"x\",0],[0,0,1,0],[0,0,0,1]]}"),
     "decals[0].matrix[1][2]: expected a number"},
    {"ZeroScale", D("{" T ", \"translate\": [1,2,3], \"scale\": [1,0,1]}"),
     "decals[0].scale: not invertible (degenerate decal)"},
    {"ScaleShape", D("{" T ", \"scale\": [1,2]}"), "decals[0].scale: expected a number or 3 numbers"},
    {"TranslateShape", D("{" T ", \"translate\": [1,2]}"), "decals[0].translate: expected 3 numbers"},
    {"RotateElement", D("{" T ", \"rotate_deg\": [0,null,0]}"), "decals[0].rotate_deg[1]: expected a number"},
    {"EulerAndQuaternion", D("{" T ", \"rotate_deg\": [0,0,0], \"quaternion_wxyz\": [1,0,0,0]}"),
     "decals[0]: give either 'rotate_deg' or 'quaternion_wxyz'"},
    {"ZeroQuaternion", D("{" T ", \"quaternion_wxyz\": [0,0,0,0]}"), "decals[0].quaternion_wxyz: zero quaternion"},
    {"QuaternionShape", D("{" T ", \"quaternion_wxyz\": [1,0,0]}"), "decals[0].quaternion_wxyz: expected 4 numbers"},
    {"LookAtMissingUp", D("{" T ", \"origin\": [0,0,1], \"target\": [0,0,0], \"size\": 1}"),
     "decals[0]: look-at placement needs 'origin', 'target', 'up' and 'size' (missing 'up')"},
    {"LookAtParallelUp", D("{" T ", \"origin\": [0,0,1], \"target\": [0,0,0], \"up\": [0,0,2], \"size\": 1}"),
     "decals[0].up: zero or parallel to the view direction"},
    {"LookAtSamePoint", D("{" T ", \"origin\": [1,1,1], \"target\": [1,1,1], \"up\": [0,0,1], \"size\": 1}"),
     "decals[0].target: equals 'origin'"},
    {"LookAtBadSize", D("{" T ", \"origin\": [0,0,1], \"target\": [0,0,0], \"up\": [0,1,0], \"size\": [1,0,1]}"),
     "decals[0].size: expected positive sizes"},
    {"TexturesNotObject", "{\"textures\": [], \"decals\": []}", "textures: expected an object"},
    {"TextureEntryType", "{\"textures\": {\"a\": 3}, \"decals\": []}",
     "textures.a: expected an image path or an object"},
    {"TextureEntryNoAlbedo", "{\"textures\": {\"a\": {\"alpha\": \"straight\"}}, \"decals\": []}",
     "textures.a: expected at least one map: albedo (or volume, cube, cube_faces), normal, orm, emission"},
    {"TextureEntryRoughnessMap",
     "{\"textures\": {\"a\": {\"albedo\": \"t.png\", \"roughness\": \"r.png\"}}, \"decals\": []}",
     "textures.a.roughness: not a map of its own: pack occlusion, roughness and metallic into 'orm' (R, G, B)"},
    {"TextureEntryNormalYWithoutNormal",
     "{\"textures\": {\"a\": {\"albedo\": \"t.png\", \"normal_y\": \"down\"}}, \"decals\": []}",
     "textures.a.normal_y: there is no 'normal' map to flip"},
    {"TextureEntryNormalYValue",
     "{\"textures\": {\"a\": {\"normal\": \"n.png\", \"normal_y\": \"left\"}}, \"decals\": []}",
     "textures.a.normal_y: expected one of: up, down (got 'left')"},
    {"TextureEntryUnknownKey", "{\"textures\": {\"a\": {\"albedo\": \"t.png\", \"albdo\": \"n.png\"}}, \"decals\": []}",
     "textures.a.albdo: unknown key (did you mean 'albedo'?)"},
    {"TextureEntryBadAlpha", "{\"textures\": {\"a\": {\"albedo\": \"t.png\", \"alpha\": \"pre\"}}, \"decals\": []}",
     "textures.a.alpha: expected one of: auto, straight, premultiplied (got 'pre')"},
    {"TextureEntryEmptyPath", "{\"textures\": {\"a\": \"\"}, \"decals\": []}",
     "textures.a: expected a non-empty image path"},
    {"TextureKeyQuoted", "{\"textures\": {\"my tex\": 1}, \"decals\": []}",
     "textures[\"my tex\"]: expected an image path"},
    {"MissingTextureFile",
     "{\"textures\": {\"scorch\": {\"albedo\": \"tex/scorch.png\"}}, \"decals\": [{\"texture\": \"scorch\", \"scale\": "
     "1}]}",
     "tex/scorch.png: cannot open the texture: no such file"},
    {"MissingDirectTextureFile", D("{\"texture\": \"gone.png\", \"scale\": 1}"), "gone.png: cannot open the texture: no such file"},
    {"BadInterpolation", "{\"interpolation\": \"cubic\", \"decals\": []}", "interpolation: expected one of: closest, linear (got 'cubic')"},
    {"FilterAndInterpolation", "{\"filter\": \"linear\", \"interpolation\": \"closest\", \"decals\": []}",
     "interpolation: give either 'filter' or 'interpolation'"},
    {"FormatType", "{\"format\": 1, \"decals\": []}", "format: expected a string"},
    {"HugeNumber", D("{" T ", \"scale\": 1e999}"), "the number 1e999 is out of range (a double holds up to about 1.8e308)"},
};
#undef D
#undef T

INSTANTIATE_TEST_SUITE_P(Scene, SceneErrors, ::testing::ValuesIn(kErrorCases),
                         [](const ::testing::TestParamInfo<ErrorCase>& p) { return p.param.label; });

TEST(SceneLoad, MissingTextureErrorNamesThePathAsWritten) {
    ScratchDir dir;
    const std::string path = writeScene(
        dir,
        R"({"textures": {"scorch": {"albedo": "tex/scorch.png"}}, "decals": [{"texture": "scorch", "scale": 1}]})");
    try {
        loadScene(path);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("tex/scorch.png"), std::string::npos) << e.what();
    }
}

TEST(SceneLoad, MissingSceneFileIsAnInputError) {
    ScratchDir dir;
    try {
        loadScene(dir.file("none.json"));
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        EXPECT_NE(std::string(e.what()).find(dir.file("none.json")), std::string::npos) << e.what();
    }
}

TEST(SceneLoad, NeutralDescriptiveKeysAreIgnoredOnlyNextToWorldMatrix) {
    ScratchDir dir;
    writePng(dir.file("t.png"), 1);
    const std::string path = writeScene(dir, R"({"format": "box-decals/1", "matrix_layout": "row-major",
        "kinds": {"box": "text"}, "decals": [{"name": "n", "kind": "box", "texture": "t.png",
        "world_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "blender_object": "Decal",
        "location": [5,5,5], "scale": [9,9,9], "rotation_quaternion_wxyz": [1,0,0,0]}]})");
    const DecalScene s = loadScene(path);
    expectMatrixNear(s.decals[0].world_matrix, glm::dmat4(1.0));  // location/scale are notes only
}

}  // namespace
}  // namespace decalcomp

namespace decalcomp {
namespace {

// The kinds sample loads as it is: every kind, volume and cube textures re-sliced.
TEST(SceneKinds, BlenderKindsSampleLoads) {
    const DecalScene scene = loadScene(test::dataPath("blender-kinds/scene.json"));
    ASSERT_EQ(scene.decals.size(), 7u);
    int kinds[4] = {0, 0, 0, 0};
    for (const Decal& d : scene.decals) {
        ++kinds[int(d.kind)];
        const Texture2D& t = scene.textures.at(std::size_t(d.albedo_texture));
        if (d.kind == DecalKind::Volume) {
            EXPECT_EQ(t.width, 32);
            EXPECT_EQ(t.height, 32);
            EXPECT_EQ(t.depth, 32);
            EXPECT_EQ(t.shape, TextureShape::Volume);
            EXPECT_EQ(d.filter, TextureFilter::Linear);
        }
        if (d.kind == DecalKind::Cube) {
            EXPECT_EQ(t.depth, 6);
            EXPECT_EQ(t.width, t.height);
            EXPECT_EQ(t.shape, TextureShape::Cube);  // from six face files
        }
        if (d.kind == DecalKind::Box) {
            EXPECT_EQ(t.shape, TextureShape::Flat);
        }
        if (d.kind == DecalKind::Frustum) {
            EXPECT_DOUBLE_EQ(d.fov_y_deg, 40.0);
            EXPECT_DOUBLE_EQ(d.aspect, 1.3);
            EXPECT_DOUBLE_EQ(d.near, 0.2);
            EXPECT_DOUBLE_EQ(d.far, 15.0);
        }
    }
    EXPECT_EQ(kinds[int(DecalKind::Box)], 4);
    EXPECT_EQ(kinds[int(DecalKind::Volume)], 1);
    EXPECT_EQ(kinds[int(DecalKind::Frustum)], 1);
    EXPECT_EQ(kinds[int(DecalKind::Cube)], 1);
}

// The cube strip and the six face files hold the same texels.
TEST(SceneKinds, CubeStripEqualsFaces) {
    test::ScratchDir dir;
    const std::string kinds = test::dataPath("blender-kinds/");
    std::ofstream(dir.file("s.json")) << R"({"decals": [
        {"kind": "cube", "scale": 1, "texture": {"cube": ")" << kinds << R"(decal_floor_burst_strip.png"}},
        {"kind": "cube", "scale": 1, "texture": {"cube_faces": [")" << kinds << R"(decal_floor_burst_+x.png", ")" << kinds
                                      << R"(decal_floor_burst_-x.png", ")" << kinds << R"(decal_floor_burst_+y.png", ")"
                                      << kinds << R"(decal_floor_burst_-y.png", ")" << kinds << R"(decal_floor_burst_+z.png", ")"
                                      << kinds << R"(decal_floor_burst_-z.png"]}}]})";
    const DecalScene scene = loadScene(dir.file("s.json"));
    ASSERT_EQ(scene.textures.size(), 2u);
    EXPECT_EQ(scene.textures[0].texels, scene.textures[1].texels);
    EXPECT_EQ(scene.textures[0].depth, 6);
}

// A projector placed by origin/target/up is rigid, sits at origin and looks down -Z at target.
TEST(SceneKinds, FrustumLookAtIsRigidProjector) {
    test::ScratchDir dir;
    std::ofstream(dir.file("f.json")) << R"({"decals": [{"kind": "frustum", "texture": ")"
                                      << test::dataPath("blender/decal_ring.png")
                                      << R"(", "origin": [1, 2, 3], "target": [1, 2, 0], "up": [0, 1, 0],
        "fov_y_deg": 30, "near": 0.5, "far": 5, "fade": {"angle_deg": [30, 80], "distance": [2, 4]}}]})";
    const DecalScene scene = loadScene(dir.file("f.json"));
    const Decal& d = scene.decals.at(0);
    EXPECT_NEAR(glm::length(glm::dvec3(d.world_matrix * glm::dvec4(0, 0, -3, 1)) - glm::dvec3(1, 2, 0)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(glm::dvec3(d.world_matrix[3]) - glm::dvec3(1, 2, 3)), 0.0, 1e-12);
    EXPECT_NEAR(glm::determinant(glm::dmat3(d.world_matrix)), 1.0, 1e-12);
    EXPECT_EQ(d.angle_fade_deg, glm::dvec2(30, 80));
    EXPECT_EQ(d.distance_fade, glm::dvec2(2, 4));
    EXPECT_FALSE(d.occlusion.enabled);  // off unless asked for
}

// "occlusion": true takes the defaults, an object overrides them, false switches it off.
TEST(SceneKinds, BlastOcclusionForms) {
    test::ScratchDir dir;
    const std::string texture = test::dataPath("blender/decal_ring.png");
    std::ofstream(dir.file("o.json")) << R"({"decals": [)"
        << R"({"kind": "frustum", "texture": ")" << texture << R"(", "scale": 1, "occlusion": true},)"
        << R"({"kind": "frustum", "texture": ")" << texture << R"(", "scale": 1, "occlusion": {"resolution": 512, "bias": 3.5}},)"
        << R"({"kind": "frustum", "texture": ")" << texture << R"(", "scale": 1, "occlusion": {"_note": "defaults"}},)"
        << R"({"kind": "frustum", "texture": ")" << texture << R"(", "scale": 1, "occlusion": false}]})";
    const DecalScene scene = loadScene(dir.file("o.json"));
    ASSERT_EQ(scene.decals.size(), 4u);
    EXPECT_EQ(scene.decals[0].occlusion, (DecalOcclusion{true, 256, 2.0}));
    EXPECT_EQ(scene.decals[1].occlusion, (DecalOcclusion{true, 512, 3.5}));
    EXPECT_EQ(scene.decals[2].occlusion, (DecalOcclusion{true, 256, 2.0}));
    EXPECT_FALSE(scene.decals[3].occlusion.enabled);
}

}  // namespace
}  // namespace decalcomp
