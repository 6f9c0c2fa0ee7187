#pragma once
// Reading fields of JSON files (scene, camera, per-frame cameras, renderer profiles) in one place,
// with one message format: every error is Error(ErrorKind::Input) "FILE: JSON.PATH: what"
// ("scene.json: decals[3].fade.angle_deg: expected two numbers"), or "FILE: what" at the root.
// Readers of a value's type say "expected ..."; a missing key is "PARENT: missing 'key'" and an
// unknown one "PARENT.key: unknown key (did you mean 'x'?)" or "(supported: a, b)".
#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "decalcomp/error.hpp"

namespace decalcomp {

// "decals[3]" from "decals" and 3; "textures.scorch" for keys that read as identifiers (a letter or
// '_' first, then letters, digits, '_' or '-'), textures["my tex"] / frames["1"] otherwise.
std::string jsonKeyPath(const std::string& parent, const std::string& key);
std::string jsonIndexPath(const std::string& parent, std::size_t index);

// The key of `known` that `key` most likely misspells (within two edits), if any.
std::optional<std::string> closestJsonKey(const std::string& key, const std::vector<std::string>& known);

// Parses JSON text (comments allowed). A syntax error is "SOURCE: not valid JSON at line L column C
// (reason)", on one line.
nlohmann::json parseJsonText(const std::string& text, const std::string& source);
// Reads and parses a file; "FILE: cannot open the WHAT" when it cannot be read.
nlohmann::json readJsonFile(const std::string& file, const std::string& what);

// The error "FILE: PATH: what" ("FILE: what" for an empty path), for callers that kept only where
// a value was (a texture's JSON path, reported when the file fails to decode).
Error jsonFieldError(const std::string& file, const std::string& path, const std::string& what);

// A matrix as files write it: 4 rows of 4 numbers (row-major M[row][col]).
nlohmann::json matrixRowsJson(const glm::dmat4& m);

// A value of a JSON document and where it is (file and JSON path), with typed readers. The
// document must outlive the field.
class JsonField {
public:
    JsonField(const nlohmann::json& value, std::string file, std::string path = {});

    const nlohmann::json& value() const { return *value_; }
    const std::string& file() const { return file_; }
    const std::string& path() const { return path_; }

    // The error "FILE: PATH: what" ("FILE: what" at the root).
    Error error(const std::string& what) const;
    [[noreturn]] void fail(const std::string& what) const;

    // ---- structure ----
    bool isObject() const { return value_->is_object(); }
    bool isArray() const { return value_->is_array(); }
    bool has(const std::string& key) const { return value_->is_object() && value_->contains(key); }
    // Fail "expected <what>" unless the value is an object / an array (of `size` elements if given).
    const JsonField& requireObject(std::string_view what = "an object") const;
    const JsonField& requireArray(std::string_view what = "an array", std::optional<std::size_t> size = {}) const;
    // A member that must be there ("missing 'key' (hint)" otherwise).
    JsonField required(const std::string& key, std::string_view hint = {}) const;
    std::optional<JsonField> optional(const std::string& key) const;
    // Members and elements, each with its path.
    JsonField operator[](std::size_t index) const;
    std::vector<std::pair<std::string, JsonField>> members() const;
    std::vector<JsonField> elements() const;
    std::size_t size() const { return value_->size(); }
    // Fails at the first key that is neither in `known` nor a note (a key starting with '_'):
    // "unknown key (did you mean 'x'?)", else "unknown key (supported: ...)" when `known` is short.
    void checkKeys(const std::vector<std::string>& known) const;
    // The unknown-key error for member `key` (for callers that accept more than one key list).
    [[noreturn]] void failUnknownKey(const std::string& key, const std::vector<std::string>& known) const;
    static bool isNoteKey(const std::string& key) { return !key.empty() && key[0] == '_'; }

    // ---- values ----
    double number() const;                        // "expected a number" (finite)
    double numberIn(double lo, double hi) const;  // "expected a number in [lo, hi]"
    // A whole number (3.0 counts as 3): "expected an integer", "expected an integer in [lo, hi]".
    std::int64_t integer(std::int64_t lo, std::int64_t hi) const;
    int integer() const;  // in int's range
    bool boolean() const;                                  // "expected true or false"
    std::string string() const;                            // "expected a string"
    std::string nonEmptyString(std::string_view noun) const;  // also "expected a non-empty <noun>"
    // The index of the string among `names`: "expected one of: a, b, c (got 'x')".
    std::size_t choice(const std::vector<std::string_view>& names) const;
    // The value of `values` whose name(value) the string is.
    template <typename E, std::size_t N>
    E choice(const std::array<E, N>& values, const char* (*name)(E)) const {
        std::vector<std::string_view> names;
        for (E v : values) names.push_back(name(v));
        return values[choice(names)];
    }
    glm::dvec2 numberPair() const;  // "expected two numbers"
    glm::dvec3 vec3() const;        // "expected 3 numbers"
    // One number for all three components, or 3 numbers: "expected <shape>".
    glm::dvec3 vec3OrScalar(std::string_view shape = "a number or 3 numbers") const;
    // 4 rows of 4 numbers, row-major: "expected 4 rows of 4 numbers (row-major)".
    glm::dmat4 matrix4() const;
    // The same, and invertible: "expected an invertible matrix".
    glm::dmat4 invertibleMatrix4() const;

    // ---- optional members: nullopt when the key is absent, else read as above ----
    std::optional<double> optionalNumber(const std::string& key) const;
    std::optional<int> optionalInteger(const std::string& key) const;
    std::optional<bool> optionalBoolean(const std::string& key) const;
    std::optional<std::string> optionalString(const std::string& key) const;
    std::optional<glm::dvec3> optionalVec3(const std::string& key) const;
    std::optional<glm::dmat4> optionalMatrix4(const std::string& key) const;

private:
    const nlohmann::json* value_;
    std::string file_, path_;
    JsonField child(const nlohmann::json& value, std::string path) const { return {value, file_, std::move(path)}; }
    JsonField member(const std::string& key) const;
};

}  // namespace decalcomp
