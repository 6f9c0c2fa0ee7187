// Cryptomatte as specified by Psyop (v1.2): MurmurHash3_32 ids stored as floats
// ("uint32_to_float32"), metadata cryptomatte/<key>/{name,hash,conversion,manifest,manif_file},
// and the name patterns decal masks select with.
#include "decalcomp/cryptomatte.hpp"

#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "decalcomp/error.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp {

// ---- MurmurHash3 (x86, 32-bit), written from the published description ----

namespace {

constexpr std::uint32_t rotateLeft(std::uint32_t x, int r) { return (x << r) | (x >> (32 - r)); }

// The per-block scramble, applied to every full 4-byte block and to the zero-padded tail.
constexpr std::uint32_t scramble(std::uint32_t k) {
    k *= 0xcc9e2d51u;
    k = rotateLeft(k, 15);
    k *= 0x1b873593u;
    return k;
}

// Final avalanche.
constexpr std::uint32_t finalMix(std::uint32_t h) {
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

}  // namespace

std::uint32_t murmurHash3_32(std::string_view data, std::uint32_t seed) {
    const auto byte = [&](std::size_t i) { return std::uint32_t(static_cast<unsigned char>(data[i])); };
    const std::size_t length = data.size();
    const std::size_t full = length / 4 * 4;
    std::uint32_t h = seed;
    for (std::size_t i = 0; i < full; i += 4) {
        // blocks are read little-endian whatever the host
        const std::uint32_t k = byte(i) | byte(i + 1) << 8 | byte(i + 2) << 16 | byte(i + 3) << 24;
        h ^= scramble(k);
        h = rotateLeft(h, 13);
        h = h * 5u + 0xe6546b64u;
    }
    std::uint32_t tail = 0;
    for (std::size_t i = length; i > full; --i) tail = tail << 8 | byte(i - 1);
    if (length > full) h ^= scramble(tail);
    h ^= std::uint32_t(length);  // the length modulo 2^32, as the algorithm defines it
    return finalMix(h);
}

std::uint32_t cryptomatteBitsFromHash(std::uint32_t hash) {
    const std::uint32_t exponent = std::clamp<std::uint32_t>((hash >> 23) & 0xffu, 1u, 254u);
    return (hash & 0x807fffffu) | exponent << 23;
}

float cryptomatteFloatFromHash(std::uint32_t hash) {
    const std::uint32_t bits = cryptomatteBitsFromHash(hash);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

// ---- metadata ----

namespace fs = std::filesystem;
using json = nlohmann::json;

std::vector<CryptomatteLayer> cryptomatteLayers(const std::vector<ExrImage>& files) {
    constexpr std::string_view prefix = "cryptomatte/";
    std::vector<CryptomatteLayer> layers;
    for (std::size_t f = 0; f < files.size(); ++f) {
        std::map<std::string, CryptomatteLayer> by_key;  // one file's layers, by key
        for (const ExrPart& part : files[f].parts)
            for (auto it = part.header.begin(); it != part.header.end(); ++it) {
                const std::string name = it.name();
                if (!name.starts_with(prefix)) continue;
                const auto slash = name.find('/', prefix.size());
                if (slash == std::string::npos) continue;
                const auto* value = dynamic_cast<const Imf::StringAttribute*>(&it.attribute());
                if (!value) continue;
                const std::string key = name.substr(prefix.size(), slash - prefix.size());
                const std::string field = name.substr(slash + 1);
                CryptomatteLayer& layer = by_key[key];
                layer.file = files[f].path;
                layer.file_index = f;
                layer.key = key;
                if (field == "name") layer.name = value->value();
                else if (field == "hash") layer.hash = value->value();
                else if (field == "conversion") layer.conversion = value->value();
                else if (field == "manifest") layer.manifest = value->value();
                else if (field == "manif_file") layer.manif_file = value->value();
            }
        for (auto& [key, layer] : by_key)
            if (!layer.name.empty()) layers.push_back(std::move(layer));
    }
    return layers;
}

std::string cryptomatteSidecarPath(const CryptomatteLayer& layer) {
    if (layer.manif_file.empty()) return {};
    fs::path sidecar(layer.manif_file);
    if (sidecar.is_relative()) sidecar = fs::path(layer.file).parent_path() / sidecar;
    return sidecar.lexically_normal().string();
}

// ---- manifests ----

namespace {

// What an unusable manifest means for the masks, appended to every manifest warning.
constexpr const char* kKeyedByHash =
    "names select by their MurmurHash3 hash instead, so exact names still work but wildcards match nothing";

std::optional<std::uint32_t> parseHex(const std::string& s) {
    if (s.empty() || s.size() > 8) return std::nullopt;
    std::uint32_t v = 0;
    for (char c : s) {
        int d;
        if (c >= '0' && c <= '9') d = c - '0';
        else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
        else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
        else return std::nullopt;
        v = v << 4 | std::uint32_t(d);
    }
    return v;
}

// A JSON value for a message, cut short when it is long.
std::string shortDump(const json& v) {
    constexpr std::size_t kMax = 40;
    std::string text = v.dump();
    if (text.size() > kMax) text.replace(kMax, std::string::npos, "...");
    return text;
}

// The sidecar's text, or nullopt with a warning saying why it cannot be read.
std::optional<std::string> readSidecar(const CryptomatteLayer& layer, const std::string& where,
                                       CryptomatteManifest& manifest) {
    const std::string path = cryptomatteSidecarPath(layer);
    const std::string shown = path == layer.manif_file ? fmt::format("'{}'", path)
                                                       : fmt::format("'{}' ({})", layer.manif_file, path);
    std::error_code ec;
    std::string problem;
    if (!fs::exists(path, ec)) problem = "does not exist";
    else if (!fs::is_regular_file(path, ec)) problem = "is not a file";
    if (problem.empty()) {
        std::ifstream in(path, std::ios::binary);
        std::stringstream buffer;
        buffer << in.rdbuf();
        if (in) return buffer.str();
        problem = "cannot be read";
    }
    manifest.warnings.push_back(fmt::format("{}: the sidecar manifest {} {}; {} (check that the manifest was copied "
                                            "beside the EXR)",
                                            where, shown, problem, kKeyedByHash));
    return std::nullopt;
}

// Reads the name -> hash entries of parsed manifest JSON into `manifest`.
void readEntries(const json& parsed, const std::string& where, CryptomatteManifest& manifest) {
    const JsonField root(parsed, where);
    if (!root.isObject()) {
        manifest.readable = false;
        manifest.warnings.push_back(fmt::format("{}: expected a JSON object mapping names to 8-digit hexadecimal ids, "
                                                "got {}; {} (check what wrote the file)",
                                                where, parsed.type_name(), kKeyedByHash));
        return;
    }
    std::size_t bad = 0;
    std::string first_bad;
    for (const auto& [name, value] : root.members()) {
        const json& v = value.value();
        const auto hash = v.is_string() ? parseHex(v.get<std::string>()) : std::nullopt;
        if (hash) {
            manifest.names[name] = *hash;
        } else if (bad++ == 0) {
            first_bad = value.error(fmt::format("expected an id of 8 hexadecimal digits, got {}", shortDump(v))).what();
        }
    }
    if (bad == 1)
        manifest.warnings.push_back(first_bad + "; the entry is left out, so its name selects by its MurmurHash3 hash");
    else if (bad > 1)
        manifest.warnings.push_back(fmt::format("{} ({} more like it); these entries are left out, so their names "
                                                "select by their MurmurHash3 hash",
                                                first_bad, bad - 1));
}

}  // namespace

CryptomatteManifest cryptomatteManifest(const CryptomatteLayer& layer, const std::string& shown_as) {
    CryptomatteManifest manifest;
    const std::string& file = shown_as.empty() ? layer.file : shown_as;
    std::string where;
    std::optional<std::string> text;
    if (!layer.manifest.empty()) {
        manifest.source = CryptomatteManifest::Source::Header;
        where = fmt::format("{}: cryptomatte/{}/manifest", file, layer.key);
        text = layer.manifest;
    } else if (!layer.manif_file.empty()) {
        manifest.source = CryptomatteManifest::Source::Sidecar;
        where = fmt::format("{}: cryptomatte/{}/manif_file", file, layer.key);
        text = readSidecar(layer, where, manifest);
        if (text) where += ": " + cryptomatteSidecarPath(layer);
    } else {
        // Optional in the specification, but without it only exact names can select.
        manifest.warnings.push_back(fmt::format("{}: cryptomatte/{}/manifest: layer {} has no manifest (nor a "
                                                "manif_file); {} (check that the renderer writes the Cryptomatte "
                                                "manifest)",
                                                file, layer.key, layer.name, kKeyedByHash));
        return manifest;
    }
    if (!text) {
        manifest.readable = false;
        return manifest;
    }
    json parsed;
    try {
        parsed = parseJsonText(*text, where);
    } catch (const Error& e) {
        manifest.readable = false;
        manifest.warnings.push_back(fmt::format("{}; {} (check what wrote the manifest)", e.what(), kKeyedByHash));
        return manifest;
    }
    readEntries(parsed, where, manifest);
    return manifest;
}

// ---- UTF-8 ----

namespace {

constexpr char32_t kInvalidByteBase = 0x110000;  // above every code point

bool continuation(unsigned char b) { return (b & 0xc0) == 0x80; }

// The length of the valid UTF-8 sequence at text[i], or 0 (overlong forms, surrogates and values
// above U+10FFFF are not valid).
std::size_t sequenceLength(std::string_view text, std::size_t i) {
    const auto at = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char b = at(i);
    const std::size_t left = text.size() - i;
    if (b < 0x80) return 1;
    if (b >= 0xc2 && b <= 0xdf) return left >= 2 && continuation(at(i + 1)) ? 2 : 0;
    if (b >= 0xe0 && b <= 0xef) {
        if (left < 3 || !continuation(at(i + 1)) || !continuation(at(i + 2))) return 0;
        if (b == 0xe0 && at(i + 1) < 0xa0) return 0;   // overlong
        if (b == 0xed && at(i + 1) >= 0xa0) return 0;  // surrogate
        return 3;
    }
    if (b >= 0xf0 && b <= 0xf4) {
        if (left < 4 || !continuation(at(i + 1)) || !continuation(at(i + 2)) || !continuation(at(i + 3))) return 0;
        if (b == 0xf0 && at(i + 1) < 0x90) return 0;   // overlong
        if (b == 0xf4 && at(i + 1) >= 0x90) return 0;  // above U+10FFFF
        return 4;
    }
    return 0;
}

void appendUtf8(std::string& out, char32_t c) {
    if (c >= kInvalidByteBase) {
        out += char(c - kInvalidByteBase);  // an invalid byte goes back as it was
    } else if (c < 0x80) {
        out += char(c);
    } else if (c < 0x800) {
        out += char(0xc0 | (c >> 6));
        out += char(0x80 | (c & 0x3f));
    } else if (c < 0x10000) {
        out += char(0xe0 | (c >> 12));
        out += char(0x80 | ((c >> 6) & 0x3f));
        out += char(0x80 | (c & 0x3f));
    } else {
        out += char(0xf0 | (c >> 18));
        out += char(0x80 | ((c >> 12) & 0x3f));
        out += char(0x80 | ((c >> 6) & 0x3f));
        out += char(0x80 | (c & 0x3f));
    }
}

}  // namespace

std::u32string decodeUtf8Lenient(std::string_view text) {
    std::u32string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        const std::size_t n = sequenceLength(text, i);
        const auto b = static_cast<unsigned char>(text[i]);
        if (n == 0) {
            out += kInvalidByteBase + b;
            ++i;
            continue;
        }
        char32_t c = n == 1 ? b : n == 2 ? (b & 0x1f) : n == 3 ? (b & 0x0f) : (b & 0x07);
        for (std::size_t k = 1; k < n; ++k) c = c << 6 | (static_cast<unsigned char>(text[i + k]) & 0x3f);
        out += c;
        i += n;
    }
    return out;
}

// ---- name patterns ----

CryptomattePattern::CryptomattePattern(std::string_view text) : text_(text) {
    const std::u32string chars = decodeUtf8Lenient(text);
    const std::size_t n = chars.size();
    // One character at chars[i], `\` escapes taken; advances i.
    const auto take = [&](std::size_t& i) {
        if (chars[i] == U'\\' && i + 1 < n) ++i;
        return chars[i++];
    };
    for (std::size_t i = 0; i < n;) {
        const char32_t c = chars[i];
        if (c == U'\\' && i + 1 == n)
            throw inputError("ends with a lone '\\' (a literal backslash is '\\\\', written \"\\\\\\\\\" in JSON)");
        Token token;
        if (c == U'*') {
            token.kind = Kind::AnyRun;
            ++i;
            if (!tokens_.empty() && tokens_.back().kind == Kind::AnyRun) continue;  // "**" is "*"
        } else if (c == U'?') {
            token.kind = Kind::AnyOne;
            ++i;
        } else if (c == U'[') {
            // A set: `[`, an optional `!` or `^`, members (a `]` first is one), `]`.
            std::size_t j = i + 1;
            token.kind = Kind::Set;
            if (j < n && (chars[j] == U'!' || chars[j] == U'^')) {
                token.negated = true;
                ++j;
            }
            bool first = true;
            while (j < n && (first || chars[j] != U']')) {
                const char32_t lo = take(j);
                char32_t hi = lo;
                if (j + 1 < n && chars[j] == U'-' && chars[j + 1] != U']') {
                    ++j;
                    hi = take(j);
                }
                token.ranges.push_back({lo, hi});
                first = false;
            }
            if (j >= n) {  // no closing ']': the '[' is an ordinary character
                token = Token{Kind::Char, U'[', false, {}};
                ++i;
            } else {
                i = j + 1;
            }
        } else {
            token.kind = Kind::Char;
            token.ch = take(i);
        }
        if (token.kind == Kind::Char) appendUtf8(literal_, token.ch);
        else wildcards_ = true;
        tokens_.push_back(std::move(token));
    }
}

bool CryptomattePattern::matchesOne(const Token& token, char32_t ch) const {
    switch (token.kind) {
        case Kind::Char: return token.ch == ch;
        case Kind::AnyOne: return true;
        case Kind::Set: {
            const bool in = std::any_of(token.ranges.begin(), token.ranges.end(),
                                        [&](const Range& r) { return r.first <= ch && ch <= r.last; });
            return in != token.negated;
        }
        case Kind::AnyRun: return false;
    }
    return false;
}

// Every token but `*` matches exactly one character, so on a mismatch it is enough to let the last
// `*` take one more character and retry (no deeper backtracking is ever needed).
bool CryptomattePattern::matches(std::string_view name) const {
    const std::u32string chars = decodeUtf8Lenient(name);
    constexpr std::size_t none = std::size_t(-1);
    std::size_t t = 0, c = 0, star = none, star_c = 0;
    while (c < chars.size()) {
        if (t < tokens_.size() && tokens_[t].kind == Kind::AnyRun) {
            star = t++;
            star_c = c;
        } else if (t < tokens_.size() && matchesOne(tokens_[t], chars[c])) {
            ++t;
            ++c;
        } else if (star != none) {
            t = star + 1;
            c = ++star_c;
        } else {
            return false;
        }
    }
    while (t < tokens_.size() && tokens_[t].kind == Kind::AnyRun) ++t;
    return t == tokens_.size();
}

}  // namespace decalcomp
