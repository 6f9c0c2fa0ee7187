// The "mask" field of scene decals: ids, exclude_ids, Cryptomatte names; sharing of identical
// masks; errors that name the JSON path.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>

#include "decalcomp/error.hpp"
#include "decalcomp/scene.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using test::ScratchDir;
namespace fs = std::filesystem;

void writePng(const std::string& path) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(1, 1, 4, OIIO::TypeDesc::UINT8);
    const std::uint8_t px[] = {255, 0, 0, 255};
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    ASSERT_TRUE(out->close());
}

// A scene with texture "t" and the given decals array text.
struct MaskFixture {
    ScratchDir dir;
    MaskFixture() { writePng(dir.file("t.png")); }
    std::string scene(const std::string& decals) {
        const std::string path = dir.file("scene.json");
        std::ofstream(path) << R"({"textures": {"t": "t.png"}, "decals": )" << decals << "}";
        return path;
    }
    // One decal with the given mask text.
    std::string withMask(const std::string& mask) {
        return scene(R"([{"name": "a", "texture": "t", "scale": 1, "mask": )" + mask + "}]");
    }
};

TEST(MaskJson, FieldsAreRead) {
    MaskFixture f;
    const DecalScene s = loadScene(f.withMask(
        R"({"ids": [4, 3, 4], "exclude_ids": [7], "cryptomatte": {"layer": "CryptoMaterial", "names": ["M_Wall*", "Floor"]}})"));
    ASSERT_EQ(s.masks.size(), 1u);
    ASSERT_EQ(s.decals[0].mask, 0);
    const DecalMask& m = s.masks[0];
    EXPECT_EQ(m.include_ids, (std::vector<int>{3, 4}));  // sorted, duplicates dropped
    EXPECT_EQ(m.exclude_ids, (std::vector<int>{7}));
    EXPECT_EQ(m.cryptomatte_layer, "CryptoMaterial");
    EXPECT_EQ(m.cryptomatte_names, (std::vector<std::string>{"M_Wall*", "Floor"}));  // order kept
}

TEST(MaskJson, AnySubsetAndDefaults) {
    MaskFixture f;
    const DecalScene s = loadScene(f.scene(R"([
        {"name": "ids", "texture": "t", "scale": 1, "mask": {"ids": [2]}},
        {"name": "exclude", "texture": "t", "scale": 1, "mask": {"exclude_ids": [-1, 5.0]}},
        {"name": "crypto", "texture": "t", "scale": 1, "mask": {"cryptomatte": {"names": "Wall", "_note": 1}}},
        {"name": "plain", "texture": "t", "scale": 1}])"));
    ASSERT_EQ(s.masks.size(), 3u);
    EXPECT_EQ(s.masks[0], (DecalMask{{2}, {}, "", {}}));
    EXPECT_EQ(s.masks[1], (DecalMask{{}, {-1, 5}, "", {}}));
    // No layer: CryptoObject; a single string is a one-name list.
    EXPECT_EQ(s.masks[2], (DecalMask{{}, {}, "CryptoObject", {"Wall"}}));
    EXPECT_EQ(s.decals[3].mask, -1);
}

TEST(MaskJson, IdenticalMasksAreSharedAndIndicesSurviveReordering) {
    MaskFixture f;
    const DecalScene s = loadScene(f.scene(R"([
        {"name": "a", "texture": "t", "scale": 1, "priority": 2, "mask": {"ids": [1, 2]}},
        {"name": "b", "texture": "t", "scale": 1, "priority": 1, "mask": {"cryptomatte": {"names": ["W*"]}}},
        {"name": "c", "texture": "t", "scale": 1, "priority": 0, "mask": {"ids": [2, 1, 1]}},
        {"name": "d", "texture": "t", "scale": 1, "mask": {"cryptomatte": {"layer": "CryptoObject", "names": ["W*"]}}}])"));
    ASSERT_EQ(s.masks.size(), 2u);
    ASSERT_EQ(s.decals.size(), 4u);
    std::map<std::string, int> mask_of;
    for (const Decal& d : s.decals) mask_of[d.name] = d.mask;
    EXPECT_EQ(mask_of["a"], mask_of["c"]);
    EXPECT_EQ(mask_of["b"], mask_of["d"]);
    EXPECT_NE(mask_of["a"], mask_of["b"]);
    EXPECT_EQ(s.masks[std::size_t(mask_of["a"])].include_ids, (std::vector<int>{1, 2}));
    EXPECT_EQ(s.masks[std::size_t(mask_of["b"])].cryptomatte_names, (std::vector<std::string>{"W*"}));
}

struct MaskErrorCase {
    const char* label;
    const char* mask;      // the mask value's JSON text
    const char* expected;  // substring after "<file>: "
};

std::ostream& operator<<(std::ostream& os, const MaskErrorCase& c) { return os << c.label; }

class MaskJsonErrors : public ::testing::TestWithParam<MaskErrorCase> {};

TEST_P(MaskJsonErrors, NameTheJsonPath) {
    MaskFixture f;
    test::expectSceneError(f.withMask(GetParam().mask), GetParam().expected);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MaskJsonErrors,
    ::testing::Values(
        MaskErrorCase{"NotAnObject", R"([3])", "decals[0].mask: expected an object"},
        MaskErrorCase{"Empty", R"({})", "decals[0].mask: empty mask"},
        MaskErrorCase{"OnlyNotes", R"({"_c": 1})", "decals[0].mask: empty mask"},
        MaskErrorCase{"UnknownKey", R"({"idz": [1]})", "decals[0].mask.idz: unknown key"},
        MaskErrorCase{"IdsNotArray", R"({"ids": 3})", "decals[0].mask.ids: expected an array"},
        MaskErrorCase{"IdsEmpty", R"({"ids": []})", "decals[0].mask.ids: expected at least one id"},
        MaskErrorCase{"IdNotInteger", R"({"ids": [3, "x"]})", "decals[0].mask.ids[1]: expected an integer"},
        MaskErrorCase{"IdFraction", R"({"exclude_ids": [1.5]})", "decals[0].mask.exclude_ids[0]: expected an integer"},
        MaskErrorCase{"IdTooLarge", R"({"ids": [3000000000]})", "decals[0].mask.ids[0]: expected an integer in [-2147483648, 2147483647]"},
        MaskErrorCase{"IdBoolean", R"({"ids": [true]})", "decals[0].mask.ids[0]: expected an integer"},
        MaskErrorCase{"CryptoNotObject", R"({"cryptomatte": "Wall"})", "decals[0].mask.cryptomatte: expected an object"},
        MaskErrorCase{"CryptoNoNames", R"({"cryptomatte": {"layer": "CryptoObject"}})",
                      "decals[0].mask.cryptomatte: missing 'names'"},
        MaskErrorCase{"CryptoNamesEmpty", R"({"cryptomatte": {"names": []}})",
                      "decals[0].mask.cryptomatte.names: expected at least one name"},
        MaskErrorCase{"CryptoNameNotString", R"({"cryptomatte": {"names": ["a", 3]}})",
                      "decals[0].mask.cryptomatte.names[1]: expected a string"},
        MaskErrorCase{"CryptoNameEmpty", R"({"cryptomatte": {"names": [""]}})",
                      "decals[0].mask.cryptomatte.names[0]: expected a non-empty name"},
        MaskErrorCase{"CryptoLayerEmpty", R"({"cryptomatte": {"layer": "", "names": ["a"]}})",
                      "decals[0].mask.cryptomatte.layer: expected a non-empty layer name"},
        MaskErrorCase{"CryptoUnknownKey", R"({"cryptomatte": {"name": ["a"]}})",
                      "decals[0].mask.cryptomatte.name: unknown key"},
        MaskErrorCase{"CryptoNameEndsInBackslash", R"({"cryptomatte": {"names": ["ok", "Wall\\"]}})",
                      "decals[0].mask.cryptomatte.names[1]: ends with a lone '\\'"},
        MaskErrorCase{"CryptoSingleNameEndsInBackslash", R"({"cryptomatte": {"names": "\\"}})",
                      "decals[0].mask.cryptomatte.names: ends with a lone '\\'"}),
    [](const ::testing::TestParamInfo<MaskErrorCase>& param_info) { return std::string(param_info.param.label); });

// Names keep their escapes as written: evaluation, not loading, decides what they select.
TEST(MaskJson, EscapedAndUtf8NamesAreKeptAsWritten) {
    MaskFixture f;
    const DecalScene s = loadScene(f.withMask(R"({"cryptomatte": {"names": ["Chair\\*", "St?hle", "a\\\\b"]}})"));
    ASSERT_EQ(s.masks.size(), 1u);
    EXPECT_EQ(s.masks[0].cryptomatte_names, (std::vector<std::string>{"Chair\\*", "St?hle", "a\\\\b"}));
}

TEST(MaskJson, MisspeltMaskKeyIsSuggested) {
    MaskFixture f;
    try {
        loadScene(f.scene(R"([{"texture": "t", "scale": 1, "masks": {"ids": [1]}}])"));
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("decals[0].masks: unknown key (did you mean 'mask'?)"), std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace decalcomp
