// JSON field readers shared by every parser (include/decalcomp/json_fields.hpp).
#include "decalcomp/json_fields.hpp"

#include "decalcomp/edit_distance.hpp"
#include "decalcomp/input_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace decalcomp {

using json = nlohmann::json;

namespace {

// Lists of known keys longer than this are not spelled out in an unknown-key message.
constexpr std::size_t kMaxListedKeys = 8;

// nlohmann reports how many bytes it had read; users want the line and column of that byte.
std::pair<std::size_t, std::size_t> lineAndColumn(const std::string& text, std::size_t bytesRead) {
    const std::size_t at = std::min(bytesRead > 0 ? bytesRead - 1 : 0, text.size());
    const std::size_t line = 1 + std::size_t(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
    const std::size_t lineStart = at == 0 ? 0 : text.rfind('\n', at - 1);
    const std::size_t column = lineStart == std::string::npos || at == 0 ? at + 1 : at - lineStart;
    return {line, column};
}

// nlohmann's own message minus its "[json.exception...] parse error at ...: " prefix, on one line.
std::string parseReason(std::string reason) {
    if (reason.starts_with("[json.exception.")) reason = reason.substr(std::min(reason.size(), reason.find("] ") + 2));
    if (reason.starts_with("parse error")) reason = reason.substr(std::min(reason.size(), reason.find(": ") + 2));
    std::string out;
    for (char c : reason) out += (c == '\n') ? std::string("\\n") : (c == '\r' || c == '\t') ? " " : std::string(1, c);
    return out;
}

// Follows the JSON path through a SAX parse, to say which field a parse error (a number beyond a
// double's range) stopped at; DOM parsing only knows the byte.
class PathTracker : public nlohmann::json_sax<json> {
public:
    const std::string& errorPath() const { return error_path_; }

    bool null() override { return scalar(); }
    bool boolean(bool) override { return scalar(); }
    bool number_integer(number_integer_t) override { return scalar(); }
    bool number_unsigned(number_unsigned_t) override { return scalar(); }
    bool number_float(number_float_t, const string_t&) override { return scalar(); }
    bool string(string_t&) override { return scalar(); }
    bool binary(binary_t&) override { return scalar(); }
    bool start_object(std::size_t) override { return open(false); }
    bool start_array(std::size_t) override { return open(true); }
    bool key(string_t& key) override {
        levels_.back().key = key;
        return true;
    }
    bool end_object() override { return close(); }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
        error_path_ = valuePath();
        return false;
    }

private:
    struct Level {
        bool array = false;
        std::size_t index = 0;
        std::string key, path;
    };
    std::string valuePath() const {
        if (levels_.empty()) return "";
        const Level& top = levels_.back();
        return top.array ? jsonIndexPath(top.path, top.index) : jsonKeyPath(top.path, top.key);
    }
    bool scalar() {
        if (!levels_.empty() && levels_.back().array) ++levels_.back().index;
        return true;
    }
    bool open(bool array) {
        levels_.push_back({array, 0, "", valuePath()});
        return true;
    }
    bool close() {
        levels_.pop_back();
        return scalar();
    }
    std::vector<Level> levels_;
    std::string error_path_;
};

std::string failingJsonPath(const std::string& text) {
    PathTracker tracker;
    json::sax_parse(text, &tracker, json::input_format_t::json, /*strict=*/true, /*ignore_comments=*/true);
    return tracker.errorPath();
}

}  // namespace

std::string jsonKeyPath(const std::string& parent, const std::string& key) {
    const bool plain = !key.empty() && (std::isalpha(static_cast<unsigned char>(key[0])) || key[0] == '_') &&
                       std::all_of(key.begin(), key.end(), [](unsigned char c) {
                           return std::isalnum(c) || c == '_' || c == '-';
                       });
    if (!plain) return parent + "[" + json(key).dump() + "]";
    return parent.empty() ? key : parent + "." + key;
}

std::string jsonIndexPath(const std::string& parent, std::size_t index) { return fmt::format("{}[{}]", parent, index); }

std::optional<std::string> closestJsonKey(const std::string& key, const std::vector<std::string>& known) {
    std::optional<std::string> best;
    std::size_t bestDistance = 3;
    for (const std::string& k : known) {
        const std::size_t d = editDistance(key, k);
        if (d < bestDistance) bestDistance = d, best = k;
    }
    return best;
}

json parseJsonText(const std::string& text, const std::string& source) {
    try {
        return json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
    } catch (const json::parse_error& e) {
        const auto [line, column] = lineAndColumn(text, e.byte);
        throw inputError(
            fmt::format("{}: not valid JSON at line {} column {} ({})", source, line, column, parseReason(e.what())));
    } catch (const json::out_of_range& e) {  // a number too large for a double: say where it is
        const std::string reason = e.what();
        const std::size_t open = reason.find('\''), close = reason.rfind('\'');
        const std::string number = open < close ? reason.substr(open + 1, close - open - 1) : "";
        const std::size_t at = number.empty() ? std::string::npos : text.find(number);
        if (at == std::string::npos)
            throw inputError(fmt::format("{}: not valid JSON ({})", source, parseReason(reason)));
        const auto [line, column] = lineAndColumn(text, at + 1);
        const std::string path = failingJsonPath(text);
        throw inputError(fmt::format("{}: {}line {} column {}: the number {} is out of range (a double holds up to "
                                     "about 1.8e308)",
                                     source, path.empty() ? "" : path + ": ", line, column, number));
    } catch (const json::exception& e) {
        throw inputError(fmt::format("{}: not valid JSON ({})", source, parseReason(e.what())));
    }
}

json readJsonFile(const std::string& file, const std::string& what) {
    requireInputFile(file, what);
    std::ifstream in(file, std::ios::binary);
    std::stringstream buffer;
    buffer << in.rdbuf();
    if (!in) throw inputError(fmt::format("{}: cannot read the {}", file, what));
    return parseJsonText(buffer.str(), file);
}

json matrixRowsJson(const glm::dmat4& m) {
    json rows = json::array();
    for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
    return rows;
}

// ---- JsonField ----

JsonField::JsonField(const json& value, std::string file, std::string path)
    : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

Error jsonFieldError(const std::string& file, const std::string& path, const std::string& what) {
    if (path.empty()) return inputError(fmt::format("{}: {}", file, what));
    return inputError(fmt::format("{}: {}: {}", file, path, what));
}

Error JsonField::error(const std::string& what) const { return jsonFieldError(file_, path_, what); }

void JsonField::fail(const std::string& what) const { throw error(what); }

const JsonField& JsonField::requireObject(std::string_view what) const {
    if (!value_->is_object()) fail(fmt::format("expected {}", what));
    return *this;
}

const JsonField& JsonField::requireArray(std::string_view what, std::optional<std::size_t> size) const {
    if (!value_->is_array() || (size && value_->size() != *size)) fail(fmt::format("expected {}", what));
    return *this;
}

JsonField JsonField::member(const std::string& key) const { return child(value_->at(key), jsonKeyPath(path_, key)); }

JsonField JsonField::required(const std::string& key, std::string_view hint) const {
    if (!has(key)) fail(hint.empty() ? fmt::format("missing '{}'", key) : fmt::format("missing '{}' ({})", key, hint));
    return member(key);
}

std::optional<JsonField> JsonField::optional(const std::string& key) const {
    if (!has(key)) return std::nullopt;
    return member(key);
}

JsonField JsonField::operator[](std::size_t index) const {
    return child(value_->at(index), jsonIndexPath(path_, index));
}

std::vector<std::pair<std::string, JsonField>> JsonField::members() const {
    std::vector<std::pair<std::string, JsonField>> out;
    if (value_->is_object())
        for (const auto& [key, value] : value_->items()) out.emplace_back(key, child(value, jsonKeyPath(path_, key)));
    return out;
}

std::vector<JsonField> JsonField::elements() const {
    std::vector<JsonField> out;
    if (value_->is_array())
        for (std::size_t i = 0; i < value_->size(); ++i) out.push_back((*this)[i]);
    return out;
}

void JsonField::failUnknownKey(const std::string& key, const std::vector<std::string>& known) const {
    const JsonField at = child(*value_, jsonKeyPath(path_, key));
    if (const auto guess = closestJsonKey(key, known)) at.fail(fmt::format("unknown key (did you mean '{}'?)", *guess));
    if (known.size() <= kMaxListedKeys) at.fail(fmt::format("unknown key (supported: {})", fmt::join(known, ", ")));
    at.fail("unknown key");
}

void JsonField::checkKeys(const std::vector<std::string>& known) const {
    for (const auto& [key, value] : value_->items())
        if (!isNoteKey(key) && std::find(known.begin(), known.end(), key) == known.end()) failUnknownKey(key, known);
}

double JsonField::number() const {
    if (!value_->is_number()) fail("expected a number");
    const double d = value_->get<double>();
    if (!std::isfinite(d)) fail("expected a finite number");
    return d;
}

double JsonField::numberIn(double lo, double hi) const {
    const double d = value_->is_number() ? value_->get<double>() : std::nan("");
    if (!(d >= lo && d <= hi)) fail(fmt::format("expected a number in [{}, {}]", lo, hi));
    return d;
}

std::int64_t JsonField::integer(std::int64_t lo, std::int64_t hi) const {
    const std::string range = fmt::format("expected an integer in [{}, {}]", lo, hi);
    const json& v = *value_;
    if (v.is_number_unsigned()) {
        if (v.get<std::uint64_t>() > std::uint64_t(std::max<std::int64_t>(hi, 0))) fail(range);
        const auto i = std::int64_t(v.get<std::uint64_t>());
        if (i < lo) fail(range);
        return i;
    }
    if (v.is_number_integer()) {
        const auto i = v.get<std::int64_t>();
        if (i < lo || i > hi) fail(range);
        return i;
    }
    // 3.0 counts as 3: JSON has one number type and many writers print whole floats that way.
    const bool whole = v.is_number_float() && std::isfinite(v.get<double>()) && v.get<double>() == std::floor(v.get<double>());
    const bool fullRange = lo == INT_MIN && hi == INT_MAX;
    if (!whole) fail(fullRange ? std::string("expected an integer") : range);
    const double d = v.get<double>();
    if (!(d >= double(lo) && d <= double(hi))) fail(range);
    return std::int64_t(d);
}

int JsonField::integer() const { return int(integer(INT_MIN, INT_MAX)); }

bool JsonField::boolean() const {
    if (!value_->is_boolean()) fail("expected true or false");
    return value_->get<bool>();
}

std::string JsonField::string() const {
    if (!value_->is_string()) fail("expected a string");
    return value_->get<std::string>();
}

std::string JsonField::nonEmptyString(std::string_view noun) const {
    std::string s = string();
    if (s.empty()) fail(fmt::format("expected a non-empty {}", noun));
    return s;
}

std::size_t JsonField::choice(const std::vector<std::string_view>& names) const {
    const std::string list = fmt::format("expected one of: {}", fmt::join(names, ", "));
    if (!value_->is_string()) fail(list);
    const std::string s = value_->get<std::string>();
    const auto it = std::find(names.begin(), names.end(), s);
    if (it == names.end()) fail(fmt::format("{} (got '{}')", list, s));
    return std::size_t(it - names.begin());
}

glm::dvec2 JsonField::numberPair() const {
    requireArray("two numbers", 2);
    return {(*this)[0].number(), (*this)[1].number()};
}

glm::dvec3 JsonField::vec3() const {
    requireArray("3 numbers", 3);
    return {(*this)[0].number(), (*this)[1].number(), (*this)[2].number()};
}

glm::dvec3 JsonField::vec3OrScalar(std::string_view shape) const {
    if (value_->is_number()) return glm::dvec3(number());
    requireArray(shape, 3);
    return vec3();
}

glm::dmat4 JsonField::matrix4() const {
    const char* shape = "4 rows of 4 numbers (row-major)";
    requireArray(shape, 4);
    glm::dmat4 m;
    for (std::size_t r = 0; r < 4; ++r) {
        const JsonField row = (*this)[r];
        if (!row.isArray() || row.size() != 4) fail(fmt::format("expected {}", shape));
        for (std::size_t c = 0; c < 4; ++c) m[int(c)][int(r)] = row[c].number();  // GLM: m[col][row]
    }
    return m;
}

glm::dmat4 JsonField::invertibleMatrix4() const {
    const glm::dmat4 m = matrix4();
    const double det = glm::determinant(m);
    const glm::dmat4 inv = glm::inverse(m);
    bool finite = std::isfinite(det);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(inv[c][r]);
    if (!finite || std::abs(det) < 1e-12) fail("expected an invertible matrix");
    return m;
}

namespace {

template <typename R>
std::optional<R> readOptional(const JsonField& object, const std::string& key, R (JsonField::*read)() const) {
    const std::optional<JsonField> member = object.optional(key);
    if (!member) return std::nullopt;
    return ((*member).*read)();
}

}  // namespace

std::optional<double> JsonField::optionalNumber(const std::string& key) const {
    return readOptional(*this, key, &JsonField::number);
}
std::optional<int> JsonField::optionalInteger(const std::string& key) const {
    return readOptional<int>(*this, key, &JsonField::integer);
}
std::optional<bool> JsonField::optionalBoolean(const std::string& key) const {
    return readOptional(*this, key, &JsonField::boolean);
}
std::optional<std::string> JsonField::optionalString(const std::string& key) const {
    return readOptional(*this, key, &JsonField::string);
}
std::optional<glm::dvec3> JsonField::optionalVec3(const std::string& key) const {
    return readOptional(*this, key, &JsonField::vec3);
}
std::optional<glm::dmat4> JsonField::optionalMatrix4(const std::string& key) const {
    return readOptional(*this, key, &JsonField::matrix4);
}

}  // namespace decalcomp
