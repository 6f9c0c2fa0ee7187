// Cryptomatte as the official samples and writers have it: name patterns (escapes, UTF-8 `?`,
// manifest names with wildcard characters), channel names (r/g/b/a, R/G/B/A, Nuke's
// red/green/blue/alpha), manifests that are missing, broken or partly unreadable (warned, then
// keyed by hash), and warnings that name the file, the field and, in a batch, the frames.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "decalcomp/cryptomatte.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/masks.hpp"
#include "support/batch_fixture.hpp"
#include "support/cryptomatte_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using namespace test;  // the synthetic Cryptomatte files of support/cryptomatte_fixture.hpp
namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& needle) { return text.find(needle) != std::string::npos; }

// The one warning that contains `needle` (a test failure and "" unless exactly one does).
std::string warningWith(const std::vector<std::string>& warnings, const std::string& needle) {
    std::vector<std::string> found;
    for (const std::string& w : warnings)
        if (contains(w, needle)) found.push_back(w);
    EXPECT_EQ(found.size(), 1u) << "warnings with '" << needle << "':\n"
                                << fmt::format("{}", fmt::join(warnings, "\n"));
    return found.empty() ? "" : found.front();
}

// The pixels (of kPixels) where mask `m` has a non-zero weight.
std::vector<std::size_t> selected(const Evaluated& e, std::size_t m) {
    std::vector<std::size_t> pixels;
    for (std::size_t i = 0; i < kPixels; ++i)
        if (e.at(m, i) != 0.0f) pixels.push_back(i);
    return pixels;
}

using Pixels = std::vector<std::size_t>;

// ---- name patterns ------------------------------------------------------------------------

TEST(CryptomattePattern, ShellWildcards) {
    const auto match = [](const char* pattern, const char* name) { return CryptomattePattern(pattern).matches(name); };
    EXPECT_TRUE(match("W*", "Wall"));
    EXPECT_TRUE(match("W*", "W"));
    EXPECT_FALSE(match("W*", "aWall"));
    EXPECT_TRUE(match("*", ""));
    EXPECT_TRUE(match("**a", "a"));
    EXPECT_TRUE(match("a*b*c", "a_b_b_c"));
    EXPECT_FALSE(match("a*b*c", "a_b_b_"));
    EXPECT_TRUE(match("Fl??r", "Floor"));
    EXPECT_FALSE(match("Fl??r", "Flor"));
    EXPECT_TRUE(match("[FW]*", "Floor"));
    EXPECT_FALSE(match("[FW]*", "Box"));
    EXPECT_TRUE(match("[!F]*", "Wall"));
    EXPECT_TRUE(match("[^F]*", "Wall"));
    EXPECT_FALSE(match("[!F]*", "Floor"));
    EXPECT_TRUE(match("Box[0-9]", "Box7"));
    EXPECT_FALSE(match("Box[0-9]", "Boxa"));
    EXPECT_TRUE(match("[]]", "]"));    // a ']' first is a member
    EXPECT_TRUE(match("[a-]", "-"));   // so is a '-' last
    EXPECT_FALSE(match("wall", "Wall"));  // case-sensitive
    EXPECT_TRUE(CryptomattePattern("W*").hasWildcards());
    EXPECT_TRUE(CryptomattePattern("[ab]").hasWildcards());
}

TEST(CryptomattePattern, BackslashMakesTheNextCharacterLiteral) {
    const CryptomattePattern star(R"(Chair\*)");
    EXPECT_FALSE(star.hasWildcards());
    EXPECT_EQ(star.literal(), "Chair*");
    EXPECT_TRUE(star.matches("Chair*"));
    EXPECT_FALSE(star.matches("Chair01"));
    EXPECT_EQ(CryptomattePattern(R"(Lamp\?)").literal(), "Lamp?");
    EXPECT_EQ(CryptomattePattern(R"(\[x])").literal(), "[x]");
    EXPECT_EQ(CryptomattePattern(R"(back\\slash)").literal(), R"(back\slash)");
    EXPECT_EQ(CryptomattePattern(R"(a\b)").literal(), "ab");  // any character may be escaped
    // Escapes inside a set, and a wildcard beside an escaped one.
    EXPECT_TRUE(CryptomattePattern(R"([\]x])").matches("]"));
    const CryptomattePattern mixed(R"(A\**)");
    EXPECT_TRUE(mixed.hasWildcards());
    EXPECT_TRUE(mixed.matches("A*bc"));
    EXPECT_FALSE(mixed.matches("Abc"));
}

TEST(CryptomattePattern, UnclosedBracketIsLiteral) {
    const CryptomattePattern p("Wall[2");
    EXPECT_FALSE(p.hasWildcards());
    EXPECT_EQ(p.literal(), "Wall[2");
    EXPECT_TRUE(p.matches("Wall[2"));
}

TEST(CryptomattePattern, LoneTrailingBackslashIsAnError) {
    const std::string message = errorMessage(ErrorKind::Input, [] { CryptomattePattern(R"(Wall\)"); });
    EXPECT_TRUE(contains(message, R"(ends with a lone '\')")) << message;
}

// `?` and set members are whole UTF-8 characters, not bytes: with byte matching "St??hle" would
// select "Stühle" (ü is two bytes) and "St?hle" would not.
TEST(CryptomattePattern, QuestionMarkMatchesOneUtf8Character) {
    EXPECT_TRUE(CryptomattePattern("St?hle").matches("Stühle"));
    EXPECT_TRUE(CryptomattePattern("St?hle").matches("Stuhle"));
    EXPECT_FALSE(CryptomattePattern("St??hle").matches("Stühle"));
    EXPECT_TRUE(CryptomattePattern("St??hle").matches("Stüühle"));
    EXPECT_TRUE(CryptomattePattern("?").matches("\xF0\x9F\xAA\x91"));  // a four-byte character (U+1FA91)
    EXPECT_TRUE(CryptomattePattern("St[üö]hle").matches("Stöhle"));
    EXPECT_TRUE(CryptomattePattern("[à-ÿ]").matches("ü"));
    EXPECT_FALSE(CryptomattePattern("[à-ÿ]").matches("u"));
    EXPECT_TRUE(CryptomattePattern("*ü*").matches("Stühle"));
}

TEST(CryptomattePattern, BytesThatAreNotUtf8CountAsOneCharacterEach) {
    EXPECT_EQ(decodeUtf8Lenient("Stühle").size(), 6u);
    EXPECT_EQ(decodeUtf8Lenient("\xC0\xAF").size(), 2u);      // overlong: two invalid bytes
    EXPECT_EQ(decodeUtf8Lenient("\xED\xA0\x80").size(), 3u);  // a surrogate
    EXPECT_TRUE(CryptomattePattern("?").matches("\xFF"));
    EXPECT_TRUE(CryptomattePattern("a\xFF" "b").matches("a\xFF" "b"));
    EXPECT_EQ(CryptomattePattern("a\xFF" "b").literal(), "a\xFF" "b");
    EXPECT_FALSE(CryptomattePattern("??").matches("ü"));
}

// ---- manifests ------------------------------------------------------------------------------

CryptomatteLayer layerWithManifest(const std::string& manifest, const std::string& file = "in.exr") {
    CryptomatteLayer layer;
    layer.file = file;
    layer.key = "0a1b2c3";
    layer.name = "CryptoObject";
    layer.manifest = manifest;
    return layer;
}

TEST(CryptomatteManifest, InlineManifestIsRead) {
    const CryptomatteManifest m =
        cryptomatteManifest(layerWithManifest(R"({"bunny": "13851a76", "Stühle": "42c9679f"})"));
    EXPECT_EQ(m.source, CryptomatteManifest::Source::Header);
    EXPECT_TRUE(m.readable);
    EXPECT_TRUE(m.warnings.empty());
    EXPECT_EQ(m.names, (std::map<std::string, std::uint32_t>{{"bunny", 0x13851a76u}, {"Stühle", 0x42c9679fu}}));
}

// Optional in the specification, but without one only exact names select: worth a word.
TEST(CryptomatteManifest, NoManifestAtAllIsAWarning) {
    const CryptomatteManifest none = cryptomatteManifest(layerWithManifest(""));
    EXPECT_EQ(none.source, CryptomatteManifest::Source::None);
    EXPECT_TRUE(none.readable);
    EXPECT_TRUE(none.names.empty());
    ASSERT_EQ(none.warnings.size(), 1u);
    EXPECT_EQ(none.warnings[0].rfind("in.exr: cryptomatte/0a1b2c3/manifest: layer CryptoObject has no manifest", 0),
              0u)
        << none.warnings[0];
    EXPECT_TRUE(contains(none.warnings[0], "names select by their MurmurHash3 hash instead")) << none.warnings[0];
}

TEST(CryptomatteManifest, BrokenJsonIsAWarningNotAnError) {
    const CryptomatteManifest m = cryptomatteManifest(layerWithManifest(R"({"A": "12345678",)"));
    EXPECT_FALSE(m.readable);
    EXPECT_TRUE(m.names.empty());
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_EQ(m.warnings[0].rfind("in.exr: cryptomatte/0a1b2c3/manifest: not valid JSON at line 1", 0), 0u)
        << m.warnings[0];
    EXPECT_TRUE(contains(m.warnings[0], "names select by their MurmurHash3 hash instead")) << m.warnings[0];
}

TEST(CryptomatteManifest, JsonThatIsNotAnObjectIsAWarning) {
    const CryptomatteManifest m = cryptomatteManifest(layerWithManifest("[1, 2]"));
    EXPECT_FALSE(m.readable);
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_TRUE(contains(m.warnings[0], "in.exr: cryptomatte/0a1b2c3/manifest: expected a JSON object mapping names"))
        << m.warnings[0];
}

TEST(CryptomatteManifest, EntriesThatAreNotHashesAreLeftOutWithOneWarning) {
    const CryptomatteManifest m =
        cryptomatteManifest(layerWithManifest(R"({"A": "12x4", "B": "0000000b", "C": 5, "D": "123456789"})"));
    EXPECT_TRUE(m.readable);
    EXPECT_EQ(m.names, (std::map<std::string, std::uint32_t>{{"B", 0xbu}}));
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_TRUE(contains(m.warnings[0], "in.exr: cryptomatte/0a1b2c3/manifest: A: expected an id of 8 hexadecimal "
                                        "digits, got \"12x4\" (2 more like it)"))
        << m.warnings[0];
}

TEST(CryptomatteManifest, SidecarThatDoesNotExistIsAWarning) {
    ScratchDir dir;
    CryptomatteLayer layer = layerWithManifest("", dir.file("c.exr"));
    layer.manif_file = "missing.json";
    const CryptomatteManifest m = cryptomatteManifest(layer);
    EXPECT_EQ(m.source, CryptomatteManifest::Source::Sidecar);
    EXPECT_FALSE(m.readable);
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_TRUE(contains(m.warnings[0], dir.file("c.exr") + ": cryptomatte/0a1b2c3/manif_file: the sidecar manifest "
                                        "'missing.json' (" + dir.file("missing.json") + ") does not exist"))
        << m.warnings[0];
    EXPECT_TRUE(contains(m.warnings[0], "check that the manifest was copied beside the EXR")) << m.warnings[0];
}

TEST(CryptomatteManifest, WarningsNameTheFileAsShown) {
    const CryptomatteManifest m = cryptomatteManifest(layerWithManifest("{", "/shots/in.0007.exr"), "in.####.exr");
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_EQ(m.warnings[0].rfind("in.####.exr: cryptomatte/0a1b2c3/manifest: ", 0), 0u) << m.warnings[0];
    EXPECT_FALSE(contains(m.warnings[0], "0007")) << m.warnings[0];
}

// ---- channel names ----------------------------------------------------------------------------

// twoRankLayer's coverage sums (see cryptomatte_fixture.hpp) for masks {A, C} and {B, D}.
void expectTwoRankWeights(const Evaluated& e) {
    ASSERT_EQ(e.weights.size(), 2u);
    EXPECT_FLOAT_EQ(e.at(0, 0), 0.65f);  // A + C: rank 0 and rank 2 (the second channel set)
    EXPECT_FLOAT_EQ(e.at(0, 1), 1.0f);
    EXPECT_FLOAT_EQ(e.at(1, 0), 0.35f);  // B + D: the b/a pairs of both sets
    EXPECT_FLOAT_EQ(e.at(1, 2), 1.0f);
}

TEST(CryptomatteChannels, NukeRedGreenBlueAlphaNamesAreAccepted) {
    ScratchDir dir;
    const std::string path =
        writeSynthetic(dir.file("nuke.exr"), twoRankLayer("CryptoObject", Imf::FLOAT, kNukeSuffixes),
                       layerMetadata("CryptoObject", manifestOf({"A", "B", "C", "D"})));
    ASSERT_TRUE(test::qualifiedNames(readExr(path)).count("CryptoObject01.alpha"));
    const Evaluated e = evaluate(path, {crypto({"A", "C"}), crypto({"B", "D"})});
    EXPECT_TRUE(e.warnings.empty()) << e.warnings.front();
    expectTwoRankWeights(e);
}

TEST(CryptomatteChannels, UpperCaseRgbaNamesAreAccepted) {
    ScratchDir dir;
    const std::string path =
        writeSynthetic(dir.file("upper.exr"), twoRankLayer("CryptoObject", Imf::FLOAT, {"R", "G", "B", "A"}),
                       layerMetadata("CryptoObject", manifestOf({"A", "B", "C", "D"})));
    const Evaluated e = evaluate(path, {crypto({"A", "C"}), crypto({"B", "D"})});
    EXPECT_TRUE(e.warnings.empty()) << e.warnings.front();
    expectTwoRankWeights(e);
}

TEST(CryptomatteChannels, IncompleteRankSetNamesWhatIsMissing) {
    ScratchDir dir;
    std::vector<Channel> channels = twoRankLayer("CryptoObject", Imf::FLOAT, kNukeSuffixes);
    channels.erase(std::remove_if(channels.begin(), channels.end(),
                                  [](const Channel& c) { return c.name == "CryptoObject00.alpha"; }),
                   channels.end());
    const std::string path = writeSynthetic(dir.file("partial.exr"), channels, layerMetadata("CryptoObject", ""));
    const std::string message = errorMessage(ErrorKind::Input, [&] { evaluate(path, {crypto({"A"})}); });
    EXPECT_TRUE(contains(message, path + ": Cryptomatte layer CryptoObject: missing channel(s) CryptoObject00.alpha"))
        << message;
    EXPECT_TRUE(contains(message, ".red/.green/.blue/.alpha")) << message;
}

// ---- names with wildcard characters, escapes, UTF-8 -------------------------------------------

// One object per pixel, each named with characters that are wildcards in a pattern.
const std::vector<std::string> kWildNames = {"Chair*", "Chair01", "Lamp?", "Lamp1", "[x]", "x", "a*b", "a-long-b"};

std::string wildFile(const ScratchDir& dir, bool with_manifest) {
    PixelIds pixels;
    for (const std::string& name : kWildNames) pixels.push_back({{name, 1.0f}});
    return writeSynthetic(dir.file(with_manifest ? "wild.exr" : "wild_bare.exr"), rankLayer("CryptoObject", pixels),
                          layerMetadata("CryptoObject", with_manifest ? manifestOf(kWildNames) : ""));
}

TEST(CryptomatteNames, ManifestNameWithWildcardCharactersSelectsExactlyItself) {
    ScratchDir dir;
    const Evaluated e = evaluate(wildFile(dir, true), {crypto({"Chair*"}), crypto({"Lamp?"}), crypto({"[x]"}),
                                                       crypto({"a*b"})});
    EXPECT_TRUE(e.warnings.empty()) << e.warnings.front();
    EXPECT_EQ(selected(e, 0), Pixels{0}) << "not Chair01";
    EXPECT_EQ(selected(e, 1), Pixels{2}) << "not Lamp1";
    EXPECT_EQ(selected(e, 2), Pixels{4}) << "not x";
    EXPECT_EQ(selected(e, 3), Pixels{6}) << "not a-long-b";
}

TEST(CryptomatteNames, EscapesAndWildcardsAgainstTheManifest) {
    ScratchDir dir;
    const Evaluated e = evaluate(wildFile(dir, true), {crypto({R"(Chair\*)"}), crypto({"Chai?0*"}),
                                                       crypto({"Lamp[?1]"}), crypto({"Chair[*]"}), crypto({"a\\*b"})});
    EXPECT_TRUE(e.warnings.empty()) << e.warnings.front();
    EXPECT_EQ(selected(e, 0), Pixels{0});     // the escaped name
    EXPECT_EQ(selected(e, 1), Pixels{1});     // a pattern that is no manifest name matches as a pattern
    EXPECT_EQ(selected(e, 2), (Pixels{2, 3}));
    EXPECT_EQ(selected(e, 3), Pixels{0});     // a set is another way to write a literal '*'
    EXPECT_EQ(selected(e, 4), Pixels{6});
}

// Without a manifest an entry without wildcards is a name: its escapes are removed and the rest is
// hashed, so `Chair\*` finds the pixels of "Chair*" (the hash of the text as written, with its
// backslash, would find none).
TEST(CryptomatteNames, EscapedNamesAreHashedUnescapedWithoutAManifest) {
    ScratchDir dir;
    const PixelIds pixels = {{{"Chair*", 1.0f}}, {{"Lamp?", 1.0f}}, {{"[x]", 1.0f}}, {{R"(back\slash)", 1.0f}},
                             {{R"(Chair\*)", 1.0f}}};
    const std::string path =
        writeSynthetic(dir.file("bare.exr"), rankLayer("CryptoObject", pixels), layerMetadata("CryptoObject", ""));
    const Evaluated e = evaluate(path, {crypto({R"(Chair\*)"}), crypto({R"(Lamp\?)"}), crypto({R"(\[x])"}),
                                        crypto({R"(back\\slash)"}), crypto({"Chair*"})});
    EXPECT_EQ(selected(e, 0), Pixels{0});
    EXPECT_EQ(selected(e, 1), Pixels{1});
    EXPECT_EQ(selected(e, 2), Pixels{2});
    EXPECT_EQ(selected(e, 3), Pixels{3});
    // Unescaped, "Chair*" is a pattern, and without a manifest a pattern has no names to match.
    EXPECT_EQ(selected(e, 4), Pixels{});
    ASSERT_EQ(e.warnings.size(), 2u);  // the missing manifest, and "Chair*"
    const std::string chair = warningWith(e.warnings, "'Chair*'");
    EXPECT_TRUE(contains(chair, path + ": decal 'd4': mask.cryptomatte.names[0]: 'Chair*' matches nothing in "
                                "CryptoObject (the layer has no manifest, so wildcards have no names to match)"))
        << chair;
    EXPECT_TRUE(contains(chair, R"(\* \? \[)")) << "says how to escape: " << chair;
    EXPECT_TRUE(contains(warningWith(e.warnings, "cryptomatte/0a1b2c3/manifest"), "has no manifest"));
}

TEST(CryptomatteNames, QuestionMarkMatchesOneUtf8CharacterOfManifestNames) {
    ScratchDir dir;
    const std::vector<std::string> names = {"Stühle", "Stuhle", "Stüühle", "Tisch"};
    PixelIds pixels;
    for (const std::string& name : names) pixels.push_back({{name, 1.0f}});
    const std::string path = writeSynthetic(dir.file("utf8.exr"), rankLayer("CryptoObject", pixels),
                                            layerMetadata("CryptoObject", manifestOf(names)));
    const Evaluated e = evaluate(path, {crypto({"St?hle"}), crypto({"St??hle"}), crypto({"St[üu]hle"}),
                                        crypto({"*ü*"}), crypto({"Stühle"})});
    EXPECT_TRUE(e.warnings.empty()) << e.warnings.front();
    EXPECT_EQ(selected(e, 0), (Pixels{0, 1}));
    EXPECT_EQ(selected(e, 1), Pixels{2});
    EXPECT_EQ(selected(e, 2), (Pixels{0, 1}));
    EXPECT_EQ(selected(e, 3), (Pixels{0, 2}));
    EXPECT_EQ(selected(e, 4), Pixels{0});
}

// ---- missing and broken manifests ---------------------------------------------------------------

TEST(CryptomatteManifests, MissingManifestWarnsAndKeysByHash) {
    ScratchDir dir;
    const std::string path =
        writeSynthetic(dir.file("bare.exr"), twoRankLayer("CryptoObject"), layerMetadata("CryptoObject", ""));
    const Evaluated e = evaluate(path, {crypto({"A", "C"}), crypto({"B", "D"})});
    expectTwoRankWeights(e);
    ASSERT_EQ(e.warnings.size(), 1u) << "one for the layer, not one per mask";
    EXPECT_EQ(e.warnings[0].rfind(path + ": cryptomatte/0a1b2c3/manifest: layer CryptoObject has no manifest", 0), 0u)
        << e.warnings[0];
    EXPECT_TRUE(contains(e.warnings[0], "check that the renderer writes the Cryptomatte manifest")) << e.warnings[0];
}

TEST(CryptomatteManifests, BrokenJsonManifestWarnsAndKeysByHash) {
    ScratchDir dir;
    const std::string path = writeSynthetic(dir.file("broken.exr"), twoRankLayer("CryptoObject"),
                                            layerMetadata("CryptoObject", R"({"A": "12345678",)"));
    const Evaluated e = evaluate(path, {crypto({"A", "C"}), crypto({"B*"})});
    EXPECT_FLOAT_EQ(e.at(0, 0), 0.65f) << "plain names still select, by hash";
    EXPECT_EQ(selected(e, 1), Pixels{});
    ASSERT_EQ(e.warnings.size(), 2u);
    const std::string manifest = warningWith(e.warnings, "cryptomatte/0a1b2c3/manifest");
    EXPECT_EQ(manifest.rfind(path + ": cryptomatte/0a1b2c3/manifest: not valid JSON", 0), 0u) << manifest;
    EXPECT_TRUE(contains(manifest, "check what wrote the manifest")) << manifest;
    const std::string name = warningWith(e.warnings, "'B*' matches nothing");
    EXPECT_TRUE(contains(name, "its manifest could not be read")) << name;
}

TEST(CryptomatteManifests, PartlyBrokenManifestKeepsItsGoodEntries) {
    ScratchDir dir;
    const std::string manifest = fmt::format(R"({{"A": "{}", "B": "not hex", "C": "{}"}})", hexOf("A"), hexOf("C"));
    const std::string path = writeSynthetic(dir.file("partly.exr"), twoRankLayer("CryptoObject"),
                                            layerMetadata("CryptoObject", manifest));
    const Evaluated e = evaluate(path, {crypto({"[AC]"}), crypto({"B"})});
    EXPECT_FLOAT_EQ(e.at(0, 0), 0.65f);
    EXPECT_FLOAT_EQ(e.at(1, 0), 0.3f) << "the entry left out still selects by hash";
    ASSERT_EQ(e.warnings.size(), 1u);
    EXPECT_TRUE(contains(e.warnings[0], path + ": cryptomatte/0a1b2c3/manifest: B: expected an id of 8 hexadecimal "
                                        "digits, got \"not hex\""))
        << e.warnings[0];
}

TEST(CryptomatteManifests, SidecarThatDoesNotExistWarnsAndKeysByHash) {
    ScratchDir dir;
    auto meta = layerMetadata("CryptoObject", "");
    meta["cryptomatte/0a1b2c3/manif_file"] = "manifest.json";
    const std::string path = writeSynthetic(dir.file("c.exr"), twoRankLayer("CryptoObject"), meta);
    const Evaluated e = evaluate(path, {crypto({"A", "C"}), crypto({"B", "D"})});
    EXPECT_FLOAT_EQ(e.at(0, 0), 0.65f);
    EXPECT_FLOAT_EQ(e.at(1, 2), 1.0f);
    ASSERT_EQ(e.warnings.size(), 1u);
    EXPECT_TRUE(contains(e.warnings[0], path + ": cryptomatte/0a1b2c3/manif_file: the sidecar manifest "
                                        "'manifest.json' (" + dir.file("manifest.json") + ") does not exist"))
        << e.warnings[0];
}

TEST(CryptomatteManifests, BrokenSidecarNamesTheSidecar) {
    ScratchDir dir;
    std::ofstream(dir.file("m.json")) << "not json";
    auto meta = layerMetadata("CryptoObject", "");
    meta["cryptomatte/0a1b2c3/manif_file"] = "m.json";
    const std::string path = writeSynthetic(dir.file("c.exr"), twoRankLayer("CryptoObject"), meta);
    const Evaluated e = evaluate(path, {crypto({"A"})});
    EXPECT_FLOAT_EQ(e.at(0, 0), 0.5f);
    ASSERT_EQ(e.warnings.size(), 1u);
    EXPECT_TRUE(contains(e.warnings[0], path + ": cryptomatte/0a1b2c3/manif_file: " + dir.file("m.json") +
                                            ": not valid JSON"))
        << e.warnings[0];
}

TEST(CryptomatteManifests, WarningsNameTheFileByItsLabel) {
    ScratchDir dir;
    const std::string path = writeSynthetic(dir.file("in.0007.exr"), twoRankLayer("CryptoObject"),
                                            layerMetadata("CryptoObject", "{broken"));
    const Evaluated e = evaluate(path, {crypto({"Nothing*"})}, {"in.####.exr"});
    ASSERT_EQ(e.warnings.size(), 2u);
    for (const std::string& w : e.warnings) {
        EXPECT_EQ(w.rfind("in.####.exr: ", 0), 0u) << w;
        EXPECT_FALSE(contains(w, "0007")) << w;
    }
}

// ---- the command line -------------------------------------------------------------------------

// scene.json (and its texture) in `dir`: decals over everything, each a 100-unit box with `mask`.
std::string maskScene(const ScratchDir& dir, const std::vector<std::pair<std::string, std::string>>& name_and_mask) {
    writeSolidPng(dir.file("red.png"), 230, 20, 20);
    nlohmann::json decals = nlohmann::json::array();
    for (const auto& [name, mask] : name_and_mask)
        decals.push_back({{"name", name}, {"texture", "red"}, {"scale", 100}, {"mask", nlohmann::json::parse(mask)}});
    const std::string path = dir.file("scene.json");
    std::ofstream(path) << nlohmann::json{{"textures", {{"red", "red.png"}}}, {"decals", decals}}.dump();
    return path;
}

// `decalcomp COMMAND INPUT --decals SCENE ... -o OUTPUT` on the CPU device with the Blender camera.
CommandResult runMasked(const std::string& command, const std::string& input, const std::string& scene,
                        const std::string& output, const std::string& more = "") {
    return runCli(command + " " + shellQuote(input) + " --decals " + shellQuote(scene) + " --camera " +
                  shellQuote(dataPath("blender/camera.json")) + " --device cpu -q -o " + shellQuote(output) + more);
}

TEST(CryptomatteCli, BrokenManifestWarnsAndTheFrameIsWritten) {
    ScratchDir dir;
    const std::string input = writeSynthetic(dir.file("in.exr"), twoRankLayer("CryptoObject"),
                                             layerMetadata("CryptoObject", "{broken"));
    const std::string out = dir.file("out.exr");
    const std::string scene = maskScene(dir, {{"hole", R"({"cryptomatte": {"names": ["A"]}})"}});
    const auto run = runMasked("composite", input, scene, out);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_TRUE(contains(run.output, "decalcomp: warning: " + input + ": cryptomatte/0a1b2c3/manifest: not valid JSON"))
        << run.output;
    EXPECT_TRUE(fs::exists(out));
}

// A sidecar manifest is one of the files a run reads, so no output may replace it.
TEST(CryptomatteCli, SidecarManifestIsNeverAnOutput) {
    ScratchDir dir;
    std::ofstream(dir.file("manifest.png")) << manifestOf({"A"});  // an odd name, but a valid sidecar
    auto meta = layerMetadata("CryptoObject", "");
    meta["cryptomatte/0a1b2c3/manif_file"] = "manifest.png";
    const std::string input = writeSynthetic(dir.file("in.exr"), twoRankLayer("CryptoObject"), meta);
    const std::string scene = maskScene(dir, {{"hole", R"({"cryptomatte": {"names": ["A"]}})"}});
    const std::string before = readFileBytes(dir.file("manifest.png"));
    const auto run = runMasked("composite", input, scene, dir.file("out.exr"),
                               " --preview " + shellQuote(dir.file("manifest.png")));
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_TRUE(contains(run.output, "which this run reads")) << run.output;
    EXPECT_EQ(readFileBytes(dir.file("manifest.png")), before);
    EXPECT_FALSE(fs::exists(dir.file("out.exr")));
}

// A five-frame sequence. Its CryptoObject layer holds "Chair" on frames 2 and 4 only (it is not
// in the manifest, so only its hash can find it); its CryptoMaterial layer has a broken manifest
// on frame 3. The batch reports each warning once, with the frames it came from (in --frames
// notation) and the sequence's pattern.
TEST(CryptomatteCli, BatchWarningsNameTheFrames) {
    ScratchDir dir;
    fs::create_directories(dir.file("in"));
    const std::string pattern = dir.file("in/shot.####.exr");
    for (int frame = 1; frame <= 5; ++frame) {
        PixelIds objects = {{{"Wall", 1.0f}}};
        if (frame % 2 == 0) objects.push_back({{"Chair", 1.0f}});
        std::vector<Channel> channels = rankLayer("CryptoObject", objects);
        const std::vector<Channel> materials = rankLayer("CryptoMaterial", {{{"M_Wall", 1.0f}}});
        channels.insert(channels.end(), materials.begin(), materials.end());
        auto meta = layerMetadata("CryptoObject", manifestOf({"Wall"}));
        meta.merge(layerMetadata("CryptoMaterial", frame == 3 ? "{broken" : manifestOf({"M_Wall"}), "1b2c3d4"));
        writeSynthetic(FramePattern(pattern).path(frame), channels, meta);
    }
    const std::string scene =
        maskScene(dir, {{"hole", R"({"cryptomatte": {"names": ["Wal*x", "Chair"]}})"},
                        {"paint", R"({"cryptomatte": {"layer": "CryptoMaterial", "names": "M_Wall"}})"}});
    const auto run = runMasked("batch", pattern, scene, dir.file("out/"));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const std::string prefix = "decalcomp: warning: ";
    EXPECT_TRUE(contains(run.output, prefix + "frames 1-5: " + pattern +
                                         ": decal 'hole': mask.cryptomatte.names[0]: 'Wal*x' matches nothing"))
        << run.output;
    EXPECT_TRUE(contains(run.output, prefix + "frames 1-5x2: " + pattern +
                                         ": decal 'hole': mask.cryptomatte.names[1]: 'Chair' matches nothing"))
        << run.output;
    EXPECT_TRUE(contains(run.output, prefix + "frame 3: " + pattern + ": cryptomatte/1b2c3d4/manifest: not valid JSON"))
        << run.output;
    EXPECT_EQ(occurrences(run.output, "'Wal*x' matches nothing"), 1u) << "once for the sequence\n" << run.output;
    EXPECT_FALSE(contains(run.output, "shot.000")) << "warnings name the pattern, not each file\n" << run.output;
}

}  // namespace
}  // namespace decalcomp
