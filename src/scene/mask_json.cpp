// Decal masks in scene files: {"ids": [...], "exclude_ids": [...],
// "cryptomatte": {"layer": "CryptoObject", "names": ["Wall*", ...]}}.
#include "scene/mask_json.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

#include "decalcomp/error.hpp"

namespace decalcomp::scene_detail {
namespace {

using json = nlohmann::json;

class MaskParser {
public:
    MaskParser(std::string path, std::string file) : path_(std::move(path)), file_(std::move(file)) {}

    DecalMask parse(const json& v) const {
        if (!v.is_object())
            fail(path_, "expected an object with 'ids', 'exclude_ids' and/or 'cryptomatte'");
        DecalMask mask;
        bool any = false;
        for (const auto& [key, value] : v.items()) {
            const std::string child = path_ + "." + key;
            if (key == "ids") {
                mask.include_ids = ids(value, child);
            } else if (key == "exclude_ids") {
                mask.exclude_ids = ids(value, child);
            } else if (key == "cryptomatte") {
                cryptomatte(value, child, mask);
            } else if (!key.empty() && key[0] == '_') {
                continue;  // notes
            } else {
                fail(child, "unknown key (expected 'ids', 'exclude_ids' or 'cryptomatte')");
            }
            any = true;
        }
        if (!any) fail(path_, "empty mask (give 'ids', 'exclude_ids' and/or 'cryptomatte')");
        return mask;
    }

private:
    std::string path_, file_;

    [[noreturn]] void fail(const std::string& path, const std::string& what) const {
        throw inputError(fmt::format("{}: {}: {}", file_, path, what));
    }

    static std::string at(const std::string& path, std::size_t i) { return fmt::format("{}[{}]", path, i); }

    std::vector<int> ids(const json& v, const std::string& path) const {
        if (!v.is_array()) fail(path, "expected an array of integer ids");
        if (v.empty()) fail(path, "expected at least one id (leave the key out to affect every id)");
        std::vector<int> out;
        for (std::size_t i = 0; i < v.size(); ++i) {
            const json& e = v[i];
            // 3.0 is accepted as 3: ids come from float passes and hand-written files alike.
            std::int64_t id = 0;
            if (e.is_number_unsigned()) {
                if (e.get<std::uint64_t>() > std::uint64_t(INT_MAX)) fail(at(path, i), "id out of range");
                id = std::int64_t(e.get<std::uint64_t>());
            } else if (e.is_number_integer()) {
                id = e.get<std::int64_t>();
            } else if (e.is_number_float() && std::abs(e.get<double>()) < 4e9 &&
                       e.get<double>() == double(std::int64_t(e.get<double>()))) {
                id = std::int64_t(e.get<double>());
            } else {
                fail(at(path, i), "expected an integer");
            }
            if (id < INT_MIN || id > INT_MAX) fail(at(path, i), "id out of range");
            out.push_back(int(id));
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    void cryptomatte(const json& v, const std::string& path, DecalMask& mask) const {
        if (!v.is_object()) fail(path, "expected an object like {\"layer\": \"CryptoObject\", \"names\": [\"Wall*\"]}");
        mask.cryptomatte_layer = kDefaultCryptomatteLayer;
        bool has_names = false;
        for (const auto& [key, value] : v.items()) {
            const std::string child = path + "." + key;
            if (key == "layer") {
                if (!value.is_string() || value.get<std::string>().empty())
                    fail(child, "expected a layer name (e.g. \"CryptoObject\")");
                mask.cryptomatte_layer = value.get<std::string>();
            } else if (key == "names") {
                mask.cryptomatte_names = names(value, child);
                has_names = true;
            } else if (key.empty() || key[0] != '_') {
                fail(child, "unknown key (expected 'layer' or 'names')");
            }
        }
        if (!has_names) fail(path, "missing 'names' (object or material names, wildcards allowed: [\"Wall*\"])");
    }

    // A single string is shorthand for a one-element list.
    std::vector<std::string> names(const json& v, const std::string& path) const {
        if (v.is_string()) return {name(v, path)};
        if (!v.is_array()) fail(path, "expected an array of names");
        if (v.empty()) fail(path, "expected at least one name");
        std::vector<std::string> out;
        for (std::size_t i = 0; i < v.size(); ++i) out.push_back(name(v[i], at(path, i)));
        return out;
    }

    std::string name(const json& v, const std::string& path) const {
        if (!v.is_string()) fail(path, "expected a string");
        if (v.get<std::string>().empty()) fail(path, "expected a non-empty name");
        return v.get<std::string>();
    }
};

}  // namespace

DecalMask parseMaskJson(const nlohmann::json& value, const std::string& path, const std::string& file) {
    return MaskParser(path, file).parse(value);
}

int parseAndInternMask(const nlohmann::json& value, const std::string& path, const std::string& file,
                       std::vector<DecalMask>& masks) {
    DecalMask mask = parseMaskJson(value, path, file);
    const auto it = std::find(masks.begin(), masks.end(), mask);
    if (it != masks.end()) return int(it - masks.begin());
    masks.push_back(std::move(mask));
    return int(masks.size()) - 1;
}

}  // namespace decalcomp::scene_detail
