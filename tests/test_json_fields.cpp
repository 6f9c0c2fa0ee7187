// The shared JSON field readers: every reader with good and bad values, and messages that name the
// file and the JSON path in one format ("FILE: PATH: expected ...").
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "decalcomp/error.hpp"
#include "decalcomp/json_fields.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

using json = nlohmann::json;

// The message of the Error(Input) that f throws.
std::string inputError(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        return e.what();
    }
    ADD_FAILURE() << "expected an input error";
    return {};
}

// A document {"v": <text>} and its member "v" at path "decals[3].v" of file "s.json".
struct Doc {
    json doc;
    explicit Doc(const std::string& text) : doc(json::parse("{\"v\": " + text + "}")) {}
    JsonField v() const { return JsonField(doc, "s.json", "decals[3]").required("v"); }
};

TEST(JsonFields, Paths) {
    EXPECT_EQ(jsonKeyPath("", "decals"), "decals");
    EXPECT_EQ(jsonKeyPath("decals[3]", "fade"), "decals[3].fade");
    EXPECT_EQ(jsonKeyPath("textures", "my tex"), "textures[\"my tex\"]");
    EXPECT_EQ(jsonKeyPath("frames", "12"), "frames[\"12\"]");
    EXPECT_EQ(jsonKeyPath("a", "_note-2"), "a._note-2");
    EXPECT_EQ(jsonIndexPath("decals", 3), "decals[3]");
    const Doc d(R"({"fade": {"angle_deg": [1, 2]}, "list": [5, 6]})");
    EXPECT_EQ(d.v().required("fade").required("angle_deg").path(), "decals[3].v.fade.angle_deg");
    EXPECT_EQ(d.v().required("list")[1].path(), "decals[3].v.list[1]");
    EXPECT_EQ(d.v().required("list").elements().at(0).path(), "decals[3].v.list[0]");
    EXPECT_EQ(d.v().members().at(0).second.path(), "decals[3].v.fade");
}

TEST(JsonFields, MessageFormat) {
    const json doc = json::object();
    EXPECT_EQ(inputError([&] { JsonField(doc, "s.json").fail("expected x"); }), "s.json: expected x");
    EXPECT_EQ(inputError([&] { JsonField(doc, "s.json", "a.b").fail("expected x"); }), "s.json: a.b: expected x");
    EXPECT_EQ(std::string(jsonFieldError("s.json", "t.a", "cannot open").what()), "s.json: t.a: cannot open");
}

TEST(JsonFields, Number) {
    EXPECT_DOUBLE_EQ(Doc("2.5").v().number(), 2.5);
    EXPECT_DOUBLE_EQ(Doc("-3").v().number(), -3.0);
    EXPECT_EQ(inputError([] { Doc("\"2\"").v().number(); }), "s.json: decals[3].v: expected a number");
    EXPECT_EQ(inputError([] { Doc("null").v().number(); }), "s.json: decals[3].v: expected a number");
    EXPECT_DOUBLE_EQ(Doc("0.5").v().numberIn(0.0, 1.0), 0.5);
    EXPECT_DOUBLE_EQ(Doc("1").v().numberIn(0.0, 1.0), 1.0);
    EXPECT_EQ(inputError([] { Doc("1.5").v().numberIn(0.0, 1.0); }), "s.json: decals[3].v: expected a number in [0, 1]");
    EXPECT_EQ(inputError([] { Doc("\"1\"").v().numberIn(0.0, 100.0); }),
              "s.json: decals[3].v: expected a number in [0, 100]");
}

TEST(JsonFields, NonFiniteNumber) {
    const json doc = {{"v", std::numeric_limits<double>::infinity()}};
    EXPECT_EQ(inputError([&] { JsonField(doc, "s.json").required("v").number(); }), "s.json: v: expected a finite number");
}

TEST(JsonFields, Integer) {
    EXPECT_EQ(Doc("7").v().integer(), 7);
    EXPECT_EQ(Doc("-7").v().integer(), -7);
    EXPECT_EQ(Doc("3.0").v().integer(), 3);  // a whole float counts
    EXPECT_EQ(Doc("2147483647").v().integer(), 2147483647);
    EXPECT_EQ(inputError([] { Doc("1.5").v().integer(); }), "s.json: decals[3].v: expected an integer");
    EXPECT_EQ(inputError([] { Doc("true").v().integer(); }), "s.json: decals[3].v: expected an integer");
    EXPECT_EQ(inputError([] { Doc("\"3\"").v().integer(); }), "s.json: decals[3].v: expected an integer");
    EXPECT_EQ(inputError([] { Doc("3000000000").v().integer(); }),
              "s.json: decals[3].v: expected an integer in [-2147483648, 2147483647]");
    EXPECT_EQ(inputError([] { Doc("-3000000000").v().integer(); }),
              "s.json: decals[3].v: expected an integer in [-2147483648, 2147483647]");
    EXPECT_EQ(inputError([] { Doc("1e300").v().integer(); }),
              "s.json: decals[3].v: expected an integer in [-2147483648, 2147483647]");
    EXPECT_EQ(Doc("16").v().integer(16, 4096), 16);
    EXPECT_EQ(Doc("64.0").v().integer(16, 4096), 64);
    for (const char* bad : {"8", "5000", "32.5", "\"32\"", "18446744073709551615"})
        EXPECT_EQ(inputError([&] { Doc(bad).v().integer(16, 4096); }), "s.json: decals[3].v: expected an integer in [16, 4096]")
            << bad;
}

TEST(JsonFields, BooleanAndString) {
    EXPECT_TRUE(Doc("true").v().boolean());
    EXPECT_FALSE(Doc("false").v().boolean());
    EXPECT_EQ(inputError([] { Doc("1").v().boolean(); }), "s.json: decals[3].v: expected true or false");
    EXPECT_EQ(Doc("\"abc\"").v().string(), "abc");
    EXPECT_EQ(Doc("\"\"").v().string(), "");
    EXPECT_EQ(inputError([] { Doc("3").v().string(); }), "s.json: decals[3].v: expected a string");
    EXPECT_EQ(Doc("\"a.png\"").v().nonEmptyString("image path"), "a.png");
    EXPECT_EQ(inputError([] { Doc("\"\"").v().nonEmptyString("image path"); }),
              "s.json: decals[3].v: expected a non-empty image path");
    EXPECT_EQ(inputError([] { Doc("[]").v().nonEmptyString("image path"); }), "s.json: decals[3].v: expected a string");
}

TEST(JsonFields, Choice) {
    EXPECT_EQ(Doc("\"linear\"").v().choice({"nearest", "linear", "mip"}), 1u);
    EXPECT_EQ(inputError([] { Doc("\"cubic\"").v().choice({"nearest", "linear", "mip"}); }),
              "s.json: decals[3].v: expected one of: nearest, linear, mip (got 'cubic')");
    EXPECT_EQ(inputError([] { Doc("2").v().choice({"nearest", "linear", "mip"}); }),
              "s.json: decals[3].v: expected one of: nearest, linear, mip");
    enum class Colour { Red, Green };
    const char* (*name)(Colour) = [](Colour c) { return c == Colour::Red ? "red" : "green"; };
    EXPECT_EQ(Doc("\"green\"").v().choice(std::array{Colour::Red, Colour::Green}, name), Colour::Green);
    EXPECT_EQ(inputError([&] { Doc("\"blue\"").v().choice(std::array{Colour::Red, Colour::Green}, name); }),
              "s.json: decals[3].v: expected one of: red, green (got 'blue')");
}

TEST(JsonFields, NumberPairAndVec3) {
    EXPECT_EQ(Doc("[60, 85]").v().numberPair(), glm::dvec2(60, 85));
    EXPECT_EQ(inputError([] { Doc("[60]").v().numberPair(); }), "s.json: decals[3].v: expected two numbers");
    EXPECT_EQ(inputError([] { Doc("60").v().numberPair(); }), "s.json: decals[3].v: expected two numbers");
    EXPECT_EQ(inputError([] { Doc("[60, \"x\"]").v().numberPair(); }), "s.json: decals[3].v[1]: expected a number");
    EXPECT_EQ(Doc("[1, 2, 3]").v().vec3(), glm::dvec3(1, 2, 3));
    EXPECT_EQ(inputError([] { Doc("[1, 2]").v().vec3(); }), "s.json: decals[3].v: expected 3 numbers");
    EXPECT_EQ(inputError([] { Doc("[1, null, 3]").v().vec3(); }), "s.json: decals[3].v[1]: expected a number");
    EXPECT_EQ(Doc("2").v().vec3OrScalar(), glm::dvec3(2));
    EXPECT_EQ(Doc("[1, 2, 3]").v().vec3OrScalar(), glm::dvec3(1, 2, 3));
    EXPECT_EQ(inputError([] { Doc("[1, 2]").v().vec3OrScalar(); }), "s.json: decals[3].v: expected a number or 3 numbers");
    EXPECT_EQ(inputError([] { Doc("\"x\"").v().vec3OrScalar("[r, g, b] or one number"); }),
              "s.json: decals[3].v: expected [r, g, b] or one number");
}

TEST(JsonFields, Matrix4IsRowMajor) {
    const glm::dmat4 m = Doc("[[1,2,3,4],[5,6,7,8],[9,10,11,12],[0,0,0,1]]").v().matrix4();
    EXPECT_EQ(m[3][0], 4.0);  // GLM m[col][row]: translation in the last column
    EXPECT_EQ(m[0][1], 5.0);
    EXPECT_EQ(m[2][2], 11.0);
    const char* shape = "s.json: decals[3].v: expected 4 rows of 4 numbers (row-major)";
    EXPECT_EQ(inputError([] { Doc("[[1,0,0,0],[0,1,0,0],[0,0,1,0]]").v().matrix4(); }), shape);
    EXPECT_EQ(inputError([] { Doc("[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]").v().matrix4(); }), shape);
    EXPECT_EQ(inputError([] { Doc("[[1,0,0,0],[0,1,0],[0,0,1,0],[0,0,0,1]]").v().matrix4(); }), shape);
    EXPECT_EQ(inputError([] { Doc("[[1,0,0,0],[0,1,\"x\",0],[0,0,1,0],[0,0,0,1]]").v().matrix4(); }),
              "s.json: decals[3].v[1][2]: expected a number");
    // Round trip through the writer.
    const json rows = matrixRowsJson(m);
    EXPECT_EQ(JsonField(rows, "w.json").matrix4(), m);
    EXPECT_EQ(rows[0], json({1.0, 2.0, 3.0, 4.0}));
}

TEST(JsonFields, InvertibleMatrix4) {
    EXPECT_EQ(Doc("[[2,0,0,1],[0,2,0,0],[0,0,2,0],[0,0,0,1]]").v().invertibleMatrix4()[0][0], 2.0);
    EXPECT_EQ(inputError([] { Doc("[[1,0,0,0],[0,1,0,0],[0,0,0,0],[0,0,0,1]]").v().invertibleMatrix4(); }),
              "s.json: decals[3].v: expected an invertible matrix");
}

TEST(JsonFields, StructureAndMissingKeys) {
    const Doc d(R"({"a": 1, "list": [1, 2]})");
    EXPECT_TRUE(d.v().has("a"));
    EXPECT_FALSE(d.v().has("b"));
    EXPECT_FALSE(d.v().optional("b").has_value());
    EXPECT_EQ(inputError([&] { d.v().required("b"); }), "s.json: decals[3].v: missing 'b'");
    EXPECT_EQ(inputError([&] { d.v().required("b", "an array of decals"); }),
              "s.json: decals[3].v: missing 'b' (an array of decals)");
    EXPECT_EQ(inputError([&] { d.v().required("a").requireObject(); }), "s.json: decals[3].v.a: expected an object");
    EXPECT_EQ(inputError([&] { d.v().required("a").requireArray("an array of ids"); }),
              "s.json: decals[3].v.a: expected an array of ids");
    EXPECT_EQ(inputError([&] { d.v().required("list").requireArray("two ids", 3); }),
              "s.json: decals[3].v.list: expected two ids");
    d.v().required("list").requireArray("two ids", 2);
}

TEST(JsonFields, OptionalReaders) {
    const Doc d(R"({"n": 2, "i": 3, "b": true, "s": "x", "v": [1, 2, 3],
                   "m": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "bad": "y"})");
    const JsonField v = d.v();
    EXPECT_EQ(v.optionalNumber("n"), 2.0);
    EXPECT_EQ(v.optionalInteger("i"), 3);
    EXPECT_EQ(v.optionalBoolean("b"), true);
    EXPECT_EQ(v.optionalString("s"), "x");
    EXPECT_EQ(v.optionalVec3("v"), glm::dvec3(1, 2, 3));
    EXPECT_EQ(v.optionalMatrix4("m"), glm::dmat4(1.0));
    EXPECT_FALSE(v.optionalNumber("none").has_value());
    EXPECT_FALSE(v.optionalInteger("none").has_value());
    EXPECT_FALSE(v.optionalBoolean("none").has_value());
    EXPECT_FALSE(v.optionalString("none").has_value());
    EXPECT_FALSE(v.optionalVec3("none").has_value());
    EXPECT_FALSE(v.optionalMatrix4("none").has_value());
    EXPECT_EQ(inputError([&] { v.optionalNumber("bad"); }), "s.json: decals[3].v.bad: expected a number");
    EXPECT_EQ(inputError([&] { v.optionalInteger("bad"); }), "s.json: decals[3].v.bad: expected an integer");
    EXPECT_EQ(inputError([&] { v.optionalBoolean("bad"); }), "s.json: decals[3].v.bad: expected true or false");
    EXPECT_EQ(inputError([&] { v.optionalString("n"); }), "s.json: decals[3].v.n: expected a string");
    EXPECT_EQ(inputError([&] { v.optionalVec3("bad"); }), "s.json: decals[3].v.bad: expected 3 numbers");
    EXPECT_EQ(inputError([&] { v.optionalMatrix4("bad"); }),
              "s.json: decals[3].v.bad: expected 4 rows of 4 numbers (row-major)");
}

TEST(JsonFields, UnknownKeys) {
    Doc(R"({"angle_deg": 1, "_note": 2})").v().checkKeys({"angle_deg", "axis"});  // notes pass
    EXPECT_EQ(inputError([] { Doc(R"({"angle": 1})").v().checkKeys({"angle_deg", "axis", "distance"}); }),
              "s.json: decals[3].v.angle: unknown key (supported: angle_deg, axis, distance)");
    EXPECT_EQ(inputError([] { Doc(R"({"axiz": 1})").v().checkKeys({"angle_deg", "axis", "distance"}); }),
              "s.json: decals[3].v.axiz: unknown key (did you mean 'axis'?)");
    EXPECT_EQ(inputError([] { Doc(R"({"my key": 1})").v().checkKeys({"a"}); }),
              "s.json: decals[3].v[\"my key\"]: unknown key (supported: a)");
    const std::vector<std::string> many = {"k1", "k2", "k3", "k4", "k5", "k6", "k7", "k8", "k9"};
    EXPECT_EQ(inputError([&] { Doc(R"({"zzzzzz": 1})").v().checkKeys(many); }), "s.json: decals[3].v.zzzzzz: unknown key");
    EXPECT_EQ(closestJsonKey("decal", {"decals", "textures"}), "decals");
    EXPECT_FALSE(closestJsonKey("zzzz", {"decals", "textures"}).has_value());
}

TEST(JsonFields, ParsingNamesLineAndColumn) {
    EXPECT_EQ(parseJsonText("{\"a\": 1 // note\n}", "s.json")["a"], 1);  // comments allowed
    const std::string message = inputError([] { parseJsonText("{\n  \"a\": [\n    1,\n  }\n", "s.json"); });
    EXPECT_EQ(message.rfind("s.json: not valid JSON at line 4 column 3 (", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(inputError([] { parseJsonText("[1e999]", "s.json"); }),
              "s.json: [0]: line 1 column 2: the number 1e999 is out of range (a double holds up to about 1.8e308)");
}

TEST(JsonFields, ReadingFiles) {
    test::ScratchDir dir;
    const std::string path = dir.file("c.json");
    std::ofstream(path) << R"({"x": [1, 2]})";
    EXPECT_EQ(readJsonFile(path, "camera file")["x"][1], 2);
    EXPECT_EQ(inputError([&] { readJsonFile(dir.file("none.json"), "camera file"); }),
              dir.file("none.json") + ": cannot open the camera file: no such file");
    EXPECT_EQ(inputError([&] { readJsonFile(dir.path().string(), "camera file"); }),
              dir.path().string() + ": is a folder, not a file; give the camera file itself");
    const std::string huge = dir.file("huge.json");
    std::ofstream(huge) << "{\n  \"x\": [1, 1e400]\n}";
    EXPECT_EQ(inputError([&] { readJsonFile(huge, "camera file"); }),
              huge + ": x[1]: line 2 column 12: the number 1e400 is out of range (a double holds up to about 1.8e308)");
}

}  // namespace
}  // namespace decalcomp
