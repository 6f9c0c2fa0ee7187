#pragma once
// Cryptomatte (Psyop specification 1.2) as decal masks read it: the MurmurHash3 ids, the layers an
// EXR header describes, their manifests, and the name patterns of `mask.cryptomatte.names`
// (docs/scene-format.md, "Masks"). evaluateMasks (decalcomp/masks.hpp) puts them together.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "decalcomp/exr_file.hpp"

namespace decalcomp {

// ---- ids ----

// MurmurHash3, x86 32-bit variant, of the bytes of `data` (Cryptomatte hashes names with seed 0).
std::uint32_t murmurHash3_32(std::string_view data, std::uint32_t seed = 0);

// The specification's "uint32_to_float32" conversion: the hash's bits as a float with the
// exponent clamped to [1, 254], so no id is zero, denormal, infinite or NaN.
float cryptomatteFloatFromHash(std::uint32_t hash);
std::uint32_t cryptomatteBitsFromHash(std::uint32_t hash);  // the bits of that float

// ---- layers and manifests ----

// One Cryptomatte layer as its metadata describes it (cryptomatte/<key>/...).
struct CryptomatteLayer {
    std::string file;            // the EXR whose header holds it
    std::size_t file_index = 0;  // that file's index in the list cryptomatteLayers was given
    std::string key;             // metadata key, e.g. "542cafa"
    std::string name;            // e.g. "ViewLayer.CryptoObject" (the channels' prefix)
    std::string hash;            // "MurmurHash3_32" (empty when absent)
    std::string conversion;      // "uint32_to_float32" (empty when absent)
    std::string manifest;        // inline manifest JSON (empty when absent)
    std::string manif_file;      // sidecar manifest path as written (empty when absent)
};

// Every layer described in the files' part headers (one entry per file and key).
std::vector<CryptomatteLayer> cryptomatteLayers(const std::vector<ExrImage>& files);

// The sidecar manifest path of a layer with `manif_file` (relative to the EXR's folder), else "".
std::string cryptomatteSidecarPath(const CryptomatteLayer& layer);

struct CryptomatteManifest {
    enum class Source { None, Header, Sidecar };
    Source source = Source::None;  // where it was meant to come from
    bool readable = true;          // false: it could not be read at all (see warnings)
    std::map<std::string, std::uint32_t> names;  // name -> hash, as written (the id float's bits)
    std::vector<std::string> warnings;  // "FILE: cryptomatte/KEY/FIELD: what is wrong; what to do"
};

// The layer's manifest, from the header (`manifest`, which wins) or the sidecar (`manif_file`).
// The specification lets decoders do without one, so nothing here throws: no manifest at all
// warns (names then select by hash alone); a sidecar that cannot be read, text that is not JSON or
// not an object come back as readable = false with a warning; entries whose value is not 8
// hexadecimal digits are dropped with one warning. Warnings name the EXR as `shown_as` (a batch
// gives its pattern, so every frame says the same), default layer.file.
CryptomatteManifest cryptomatteManifest(const CryptomatteLayer& layer, const std::string& shown_as = {});

// ---- name patterns ----

// One entry of `mask.cryptomatte.names`: a shell-style pattern over UTF-8 names, case-sensitive.
// `*` matches any run of characters, `?` exactly one character (a whole UTF-8 sequence, so "St?hle"
// matches "Stühle"), `[abc]`, `[a-z]` one character of a set and `[!abc]` (or `[^abc]`) one not in
// it; `\` makes the next character literal (`\*`, `\?`, `\[`, `\\`). A `[` without its `]` is a
// literal '['. Bytes that are not UTF-8 count as one character each.
class CryptomattePattern {
public:
    // Throws Error(Input) "ends with a lone '\'" when the last character is an unescaped backslash.
    explicit CryptomattePattern(std::string_view text);

    const std::string& text() const { return text_; }  // as written
    bool hasWildcards() const { return wildcards_; }   // an unescaped `*`, `?` or `[...]`
    // The name the text means with its escapes removed (`Chair\*` -> "Chair*"): for a pattern
    // without wildcards, the one name it matches.
    const std::string& literal() const { return literal_; }
    bool matches(std::string_view name) const;

private:
    enum class Kind { Char, AnyOne, AnyRun, Set };
    struct Range {
        char32_t first, last;
    };
    struct Token {
        Kind kind = Kind::Char;
        char32_t ch = 0;            // Char
        bool negated = false;       // Set
        std::vector<Range> ranges;  // Set
    };
    bool matchesOne(const Token& token, char32_t ch) const;

    std::string text_, literal_;
    bool wildcards_ = false;
    std::vector<Token> tokens_;
};

// The characters of UTF-8 `text`; each byte that does not start a valid sequence becomes
// 0x110000 + byte (above every code point), so invalid names still match themselves.
std::u32string decodeUtf8Lenient(std::string_view text);

}  // namespace decalcomp
