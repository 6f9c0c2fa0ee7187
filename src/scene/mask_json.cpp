// Decal masks in scene files: {"ids": [...], "exclude_ids": [...],
// "cryptomatte": {"layer": "CryptoObject", "names": ["Wall*", ...]}}.
#include "scene/mask_json.hpp"

#include <algorithm>

#include "decalcomp/cryptomatte.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp::scene_detail {
namespace {

// Sorted, without duplicates. 3.0 reads as 3: ids come from float passes and hand-written files alike.
std::vector<int> ids(const JsonField& v) {
    v.requireArray("an array of integer ids");
    if (v.size() == 0) v.fail("expected at least one id (leave the key out to affect every id)");
    std::vector<int> out;
    for (const JsonField& id : v.elements()) out.push_back(id.integer());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// A name or pattern, checked now so a mistake is a scene error rather than a frame's.
std::string namePattern(const JsonField& v) {
    std::string text = v.nonEmptyString("name");
    try {
        static_cast<void>(CryptomattePattern(text));
    } catch (const Error& e) {
        v.fail(e.what());
    }
    return text;
}

// A single string is shorthand for a one-element list.
std::vector<std::string> names(const JsonField& v) {
    if (v.value().is_string()) return {namePattern(v)};
    v.requireArray("an array of names");
    if (v.size() == 0) v.fail("expected at least one name");
    std::vector<std::string> out;
    for (const JsonField& name : v.elements()) out.push_back(namePattern(name));
    return out;
}

void cryptomatte(const JsonField& v, DecalMask& mask) {
    v.requireObject("an object like {\"layer\": \"CryptoObject\", \"names\": [\"Wall*\"]}");
    v.checkKeys({"layer", "names"});
    const auto layer = v.optional("layer");
    mask.cryptomatte_layer = layer ? layer->nonEmptyString("layer name (e.g. \"CryptoObject\")") : kDefaultCryptomatteLayer;
    mask.cryptomatte_names = names(v.required("names", "object or material names, wildcards allowed: [\"Wall*\"]"));
}

}  // namespace

DecalMask parseMaskJson(const JsonField& v) {
    v.requireObject("an object with 'ids', 'exclude_ids' and/or 'cryptomatte'");
    v.checkKeys({"ids", "exclude_ids", "cryptomatte"});
    DecalMask mask;
    const auto include = v.optional("ids"), exclude = v.optional("exclude_ids"), crypto = v.optional("cryptomatte");
    if (!include && !exclude && !crypto) v.fail("empty mask (give 'ids', 'exclude_ids' and/or 'cryptomatte')");
    if (include) mask.include_ids = ids(*include);
    if (exclude) mask.exclude_ids = ids(*exclude);
    if (crypto) cryptomatte(*crypto, mask);
    return mask;
}

int parseAndInternMask(const JsonField& value, std::vector<DecalMask>& masks) {
    return internMask(parseMaskJson(value), masks);
}

int internMask(DecalMask mask, std::vector<DecalMask>& masks) {
    const auto it = std::find(masks.begin(), masks.end(), mask);
    if (it != masks.end()) return int(it - masks.begin());
    masks.push_back(std::move(mask));
    return int(masks.size()) - 1;
}

}  // namespace decalcomp::scene_detail
