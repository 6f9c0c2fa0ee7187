// Scene files (docs/scene-format.md): JSON -> validated DecalScene with decoded textures.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "decalcomp/error.hpp"
#include "decalcomp/scene.hpp"
#include "decalcomp/textures.hpp"
#include "scene/animation_json.hpp"
#include "scene/kind_json.hpp"
#include "scene/mask_json.hpp"
#include "scene/material_json.hpp"
#include "scene/placement.hpp"

namespace decalcomp {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;
using scene_detail::composeTrs;

// Keys a decal object may carry, and those that are ignored notes (not placement or look).
const std::vector<std::string> kDecalKeys = {
    "name",   "kind",   "texture", "matrix", "world_matrix", "translate", "rotate_deg", "scale", "quaternion_wxyz",
    "origin", "target", "up",      "size",   "opacity",      "filter",    "priority",
    "frames", "fade_in", "fade_out", "keyframes", "keyframe_interpolation",  // animation_json.cpp
    "mask",                                                                    // mask_json.cpp
    "fov_y_deg", "aspect", "near", "far", "fade", "occlusion",                 // kind_json.cpp
    "affects"};                                                                // material_json.cpp
const std::vector<std::string> kDecalNotes = {"description", "blender_object"};
// Written by the neutral Blender export next to world_matrix; they restate it.
const std::vector<std::string> kWorldMatrixNotes = {"location", "scale", "rotation_quaternion_wxyz",
                                                    "volume_size", "texture_layout", "function", "faces"};
const std::vector<std::string> kTopLevelKeys = {"format", "description", "textures",
                                                "decals", "filter",      "interpolation"};
const std::vector<std::string> kTrsKeys = {"translate", "rotate_deg", "quaternion_wxyz", "scale"};
const std::vector<std::string> kLookAtKeys = {"origin", "target", "up", "size"};
// Keys of a texture-set object: the albedo under one of its layout names, the other maps, options.
const std::vector<std::string> kTextureSetKeys = {"albedo", "volume",   "cube",  "cube_faces", "normal",
                                                  "orm",    "emission", "alpha", "normal_y"};
// Single-channel maps users may expect; the format packs them into "orm".
const std::vector<std::string> kPackedIntoOrm = {"roughness", "metallic", "occlusion", "ao"};

bool contains(const std::vector<std::string>& list, const std::string& s) {
    return std::find(list.begin(), list.end(), s) != list.end();
}

bool isNoteKey(const std::string& key) { return !key.empty() && key[0] == '_'; }

// "textures.scorch" for plain identifiers, textures["my tex"] otherwise, so paths stay readable.
std::string keyPath(const std::string& parent, const std::string& key) {
    const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](unsigned char c) {
        return std::isalnum(c) || c == '_' || c == '-';
    });
    if (!plain) return parent + "[" + json(key).dump() + "]";
    return parent.empty() ? key : parent + "." + key;
}

std::string indexPath(const std::string& parent, size_t i) { return fmt::format("{}[{}]", parent, i); }

size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
            diagonal = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
        }
    }
    return row[b.size()];
}

// The known key a typo most likely meant, if any is within two edits.
std::optional<std::string> closestKey(const std::string& key, const std::vector<std::string>& known) {
    std::optional<std::string> best;
    size_t bestDistance = 3;
    for (const std::string& k : known) {
        const size_t d = editDistance(key, k);
        if (d < bestDistance) bestDistance = d, best = k;
    }
    return best;
}

std::string unknownKeyMessage(const std::string& key, const std::vector<std::string>& known) {
    const auto guess = closestKey(key, known);
    return guess ? fmt::format("unknown key (did you mean '{}'?)", *guess) : std::string("unknown key");
}

// nlohmann reports how many bytes it had read; users want the line and column of that byte.
std::pair<size_t, size_t> lineAndColumn(const std::string& text, size_t bytesRead) {
    const size_t at = std::min(bytesRead > 0 ? bytesRead - 1 : 0, text.size());
    const size_t line = 1 + size_t(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
    const size_t lineStart = at == 0 ? 0 : text.rfind('\n', at - 1);
    const size_t column = lineStart == std::string::npos || at == 0 ? at + 1 : at - lineStart;
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

// A texture as a scene names it, before its file is decoded.
struct TextureRequest {
    std::string file;      // as written in the scene file
    std::string jsonPath;  // where it was written, for messages
    AlphaMode alpha = AlphaMode::Auto;
    scene_detail::TextureLayout layout = scene_detail::TextureLayout::Image;
    std::vector<std::string> faces;  // cube faces +X,-X,+Y,-Y,+Z,-Z (layout CubeFaces)
    TextureContent content = TextureContent::Colour;
    bool flip_green = false;  // a normal map with +Y down (DirectX convention)
};

// A DirectX normal map (+Y down) as an OpenGL one: straight green g -> 1 - g, premultiplied.
void flipGreen(Texture2D& texture) {
    for (glm::vec4& t : texture.texels) t.g = t.a - t.g;
}

// A decal's texture set (seed 002): any map may be absent.
struct TextureSetRequest {
    std::optional<TextureRequest> albedo, normal, orm, emission;
    bool empty() const { return !albedo && !normal && !orm && !emission; }
};

TextureRequest imageRequest(std::string file, std::string json_path) {
    TextureRequest request;
    request.file = std::move(file);
    request.jsonPath = std::move(json_path);
    return request;
}

struct ParsedDecal {
    Decal decal;
    TextureSetRequest texture;
    int priority = 0;
};

class SceneParser {
public:
    explicit SceneParser(std::string file) : file_(std::move(file)), dir_(fs::path(file_).parent_path()) {}

    DecalScene load() {
        const json root = parseFile();
        if (!root.is_object()) fail("", "expected a JSON object with a 'decals' array");
        checkTopLevelKeys(root);
        const TextureFilter defaultFilter = parseDefaultFilter(root);
        parseTextureTable(root);
        if (!root.contains("decals")) fail("", "missing 'decals' (an array of decals)");
        const json& decals = root.at("decals");
        if (!decals.is_array()) fail("decals", "expected an array of decals");

        // Validate every decal before decoding any texture, so a typo fails fast.
        std::vector<ParsedDecal> parsed;
        for (size_t i = 0; i < decals.size(); ++i)
            parsed.push_back(parseDecal(decals[i], indexPath("decals", i), defaultFilter));

        DecalScene scene;
        scene.masks = masks_;
        for (ParsedDecal& p : parsed) {
            auto index = [&](const std::optional<TextureRequest>& r) { return r ? textureIndex(*r, scene) : -1; };
            p.decal.albedo_texture = index(p.texture.albedo);
            p.decal.normal_texture = index(p.texture.normal);
            p.decal.orm_texture = index(p.texture.orm);
            p.decal.emission_texture = index(p.texture.emission);
        }
        // Lower priority blends first; equal priorities keep file order (stable).
        std::stable_sort(parsed.begin(), parsed.end(),
                         [](const ParsedDecal& a, const ParsedDecal& b) { return a.priority < b.priority; });
        for (ParsedDecal& p : parsed) scene.decals.push_back(std::move(p.decal));
        return scene;
    }

private:
    std::string file_;
    fs::path dir_;
    std::map<std::string, TextureSetRequest> textureTable_;
    // decoded textures by (files, alpha, layout, content, flip) -> texture index
    std::map<std::tuple<std::string, AlphaMode, scene_detail::TextureLayout, TextureContent, bool>, int> loaded_;
    mutable std::vector<DecalMask> masks_;  // distinct masks, filled while parsing decals

    [[noreturn]] void fail(const std::string& path, const std::string& what) const {
        if (path.empty()) throw inputError(fmt::format("{}: {}", file_, what));
        throw inputError(fmt::format("{}: {}: {}", file_, path, what));
    }

    json parseFile() const {
        std::error_code ec;
        if (!fs::is_regular_file(file_, ec)) fail("", "cannot open scene file: no such file");
        std::ifstream in(file_, std::ios::binary);
        std::stringstream buffer;
        buffer << in.rdbuf();
        if (!in) fail("", "cannot read scene file");
        const std::string text = buffer.str();
        try {
            return json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
        } catch (const json::parse_error& e) {
            const auto [line, column] = lineAndColumn(text, e.byte);
            fail("", fmt::format("not valid JSON at line {} column {} ({})", line, column, parseReason(e.what())));
        } catch (const json::exception& e) {  // e.g. a number too large for a double
            fail("", fmt::format("not valid JSON ({})", parseReason(e.what())));
        }
    }

    // Unknown top-level keys are descriptive notes (the neutral format has many); only near
    // misspellings of real keys are errors, since "decal" for "decals" must not pass silently.
    void checkTopLevelKeys(const json& root) const {
        for (const auto& [key, value] : root.items()) {
            if (contains(kTopLevelKeys, key) || isNoteKey(key)) continue;
            if (closestKey(key, kTopLevelKeys)) fail(keyPath("", key), unknownKeyMessage(key, kTopLevelKeys));
        }
        if (root.contains("format") && !root.at("format").is_string()) fail("format", "expected a string");
    }

    TextureFilter parseFilter(const json& v, const std::string& path) const {
        const std::string name = string(v, path);
        if (name == "nearest") return TextureFilter::Nearest;
        if (name == "linear") return TextureFilter::Linear;
        if (name == "mip") return TextureFilter::Mip;
        fail(path, fmt::format("unknown filter '{}' (supported: nearest, linear, mip)", name));
    }

    // Top-level "filter", or the neutral format's "interpolation" (Cycles names), sets the default.
    TextureFilter parseDefaultFilter(const json& root) const {
        const bool hasFilter = root.contains("filter"), hasInterpolation = root.contains("interpolation");
        if (hasFilter && hasInterpolation) fail("interpolation", "give either 'filter' or 'interpolation', not both");
        if (hasFilter) return parseFilter(root.at("filter"), "filter");
        if (!hasInterpolation) return TextureFilter::Linear;
        const std::string name = string(root.at("interpolation"), "interpolation");
        if (name == "closest") return TextureFilter::Nearest;
        if (name == "linear") return TextureFilter::Linear;
        fail("interpolation", fmt::format("'{}' is not supported (supported: closest, linear)", name));
    }

    std::string string(const json& v, const std::string& path) const {
        if (!v.is_string()) fail(path, "expected a string");
        return v.get<std::string>();
    }

    double number(const json& v, const std::string& path) const {
        if (!v.is_number()) fail(path, "expected a number");
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail(path, "expected a finite number");
        return d;
    }

    glm::dvec3 vec3(const json& v, const std::string& path) const {
        if (!v.is_array() || v.size() != 3) fail(path, "expected 3 numbers");
        return {number(v[0], indexPath(path, 0)), number(v[1], indexPath(path, 1)), number(v[2], indexPath(path, 2))};
    }

    // A single number means the same value on all three axes.
    glm::dvec3 vec3OrScalar(const json& v, const std::string& path) const {
        if (v.is_number()) return glm::dvec3(number(v, path));
        if (!v.is_array() || v.size() != 3) fail(path, "expected a number or 3 numbers");
        return vec3(v, path);
    }

    void parseTextureTable(const json& root) {
        if (!root.contains("textures")) return;
        const json& table = root.at("textures");
        if (!table.is_object()) fail("textures", "expected an object mapping names to textures");
        for (const auto& [name, value] : table.items())
            textureTable_[name] = parseTexture(value, keyPath("textures", name));
    }

    // "file.png" is shorthand for {"albedo": "file.png"}.
    TextureSetRequest parseTexture(const json& v, const std::string& path) const {
        TextureSetRequest set;
        if (v.is_string()) {
            set.albedo = imageRequest(nonEmptyPath(v, path), path);
            return set;
        }
        if (!v.is_object()) fail(path, "expected an image path or an object like {\"albedo\": \"file.png\"}");
        AlphaMode alpha = AlphaMode::Auto;
        bool normal_y_down = false;
        for (const auto& [key, value] : v.items()) {
            const std::string child = keyPath(path, key);
            if (key == "albedo" || key == "volume" || key == "cube") {
                if (set.albedo) fail(child, "give one of 'albedo', 'volume', 'cube', 'cube_faces'");
                set.albedo = imageRequest(nonEmptyPath(value, child), child);
                set.albedo->layout = key == "volume" ? scene_detail::TextureLayout::VolumeStrip
                                     : key == "cube" ? scene_detail::TextureLayout::CubeStrip
                                                     : scene_detail::TextureLayout::Image;
            } else if (key == "cube_faces") {
                if (set.albedo) fail(child, "give one of 'albedo', 'volume', 'cube', 'cube_faces'");
                if (!value.is_array() || value.size() != 6) fail(child, "expected 6 image paths (+X,-X,+Y,-Y,+Z,-Z)");
                TextureRequest request;
                for (size_t f = 0; f < 6; ++f) request.faces.push_back(nonEmptyPath(value[f], indexPath(child, f)));
                request.file = request.faces[0];
                request.jsonPath = child;
                request.layout = scene_detail::TextureLayout::CubeFaces;
                set.albedo = request;
            } else if (key == "normal" || key == "orm" || key == "emission") {
                // same layout as the albedo's kind (a strip for volumes and cubes); normal and ORM are data
                TextureRequest request = imageRequest(nonEmptyPath(value, child), child);
                if (key != "emission") request.content = TextureContent::Data;
                (key == "normal" ? set.normal : key == "orm" ? set.orm : set.emission) = request;
            } else if (key == "alpha") {
                alpha = parseAlphaMode(value, child);
            } else if (key == "normal_y") {
                const std::string y = string(value, child);
                if (y != "up" && y != "down") fail(child, "expected 'up' (OpenGL) or 'down' (DirectX)");
                normal_y_down = y == "down";
            } else if (contains(kPackedIntoOrm, key)) {
                fail(child, "not a map of its own: pack occlusion, roughness and metallic into 'orm' (R, G, B)");
            } else if (!isNoteKey(key)) {
                fail(child, unknownKeyMessage(key, kTextureSetKeys));
            }
        }
        if (set.empty()) fail(path, "expected at least one map: albedo (or volume, cube, cube_faces), normal, orm, emission");
        if (normal_y_down && !set.normal) fail(keyPath(path, "normal_y"), "there is no 'normal' map to flip");
        if (set.normal) set.normal->flip_green = normal_y_down;
        for (auto* r : {&set.albedo, &set.normal, &set.orm, &set.emission})
            if (*r) (*r)->alpha = alpha;
        return set;
    }

    std::string nonEmptyPath(const json& v, const std::string& path) const {
        const std::string s = string(v, path);
        if (s.empty()) fail(path, "expected a non-empty image path");
        return s;
    }

    AlphaMode parseAlphaMode(const json& v, const std::string& path) const {
        const std::string s = string(v, path);
        if (s == "auto") return AlphaMode::Auto;
        if (s == "straight") return AlphaMode::Straight;
        if (s == "premultiplied") return AlphaMode::Premultiplied;
        fail(path, fmt::format("unknown alpha mode '{}' (supported: auto, straight, premultiplied)", s));
    }

    ParsedDecal parseDecal(const json& j, const std::string& path, TextureFilter defaultFilter) const {
        if (!j.is_object()) fail(path, "expected an object");
        // Kind first: fields of future kinds should read as "unsupported kind", not "unknown key".
        if (j.contains("kind")) {
            const std::string kind = string(j.at("kind"), path + ".kind");
            if (!scene_detail::kindFromName(kind))
                fail(path + ".kind", fmt::format("unsupported kind '{}' (supported: box, volume, frustum, cube)", kind));
        }
        checkDecalKeys(j, path);
        ParsedDecal p;
        p.decal.kind = j.contains("kind") ? *scene_detail::kindFromName(j.at("kind").get<std::string>()) : DecalKind::Box;
        p.decal.name = j.contains("name") ? string(j.at("name"), path + ".name") : path;
        if (j.contains("texture")) p.texture = textureReference(j, path);
        if (!scene_detail::parseDecalAnimation(j, path, file_, [this](const json& v, const std::string& at) { return placement(v, at); }, p.decal))
            p.decal.world_matrix = scene_detail::isProjectorLookAt(j, p.decal.kind)
                                       ? scene_detail::projectorLookAt(j, path, file_)
                                       : placement(j, path);
        scene_detail::parseKindFields(j, path, file_, p.decal);
        for (auto* r : {&p.texture.albedo, &p.texture.normal, &p.texture.orm, &p.texture.emission})
            if (*r) (*r)->layout = scene_detail::layoutForKind(p.decal.kind, (*r)->layout, (*r)->jsonPath, file_);
        if (j.contains("affects")) {
            scene_detail::parseAffects(j.at("affects"), path + ".affects", file_, p.decal);
            checkAffectedTargetsHaveValues(p, path + ".affects");
        }
        if (p.texture.empty() && !std::any_of(p.decal.effects.begin(), p.decal.effects.end(), [](const TargetEffect& e) {
                return e.value.has_value() && e.factor > 0.0f;
            }))
            fail(path, "missing 'texture' (a decal needs a texture set, or constant values in 'affects')");
        if (j.contains("opacity")) p.decal.opacity = opacity(j.at("opacity"), path + ".opacity");
        p.decal.filter = j.contains("filter") ? parseFilter(j.at("filter"), path + ".filter") : defaultFilter;
        if (j.contains("priority")) p.priority = priority(j.at("priority"), path + ".priority");
        if (j.contains("mask"))  // identical masks share one entry of DecalScene::masks
            p.decal.mask = scene_detail::parseAndInternMask(j.at("mask"), path + ".mask", file_, masks_);
        return p;
    }

    // A listed target with neither a map nor a constant would silently do nothing: a mistake.
    void checkAffectedTargetsHaveValues(const ParsedDecal& p, const std::string& path) const {
        for (int t = 0; t < kDecalTargets; ++t) {
            const auto target = DecalTarget(t);
            const TargetEffect& e = p.decal.effect(target);
            if (!(e.factor > 0.0f) || e.value) continue;
            const char* map = target == DecalTarget::Albedo     ? "albedo"
                              : target == DecalTarget::Normal   ? "normal"
                              : target == DecalTarget::Emission ? "emission"
                                                                : "orm";
            const auto& request = target == DecalTarget::Albedo     ? p.texture.albedo
                                  : target == DecalTarget::Normal   ? p.texture.normal
                                  : target == DecalTarget::Emission ? p.texture.emission
                                                                    : p.texture.orm;
            if (request) continue;
            fail(path + "." + decalTargetName(target),
                 target == DecalTarget::Normal
                     ? std::string("nothing to write: the texture set has no 'normal' map")
                     : fmt::format("nothing to write: the texture set has no '{}' map and there is no 'value'", map));
        }
    }

    void checkDecalKeys(const json& j, const std::string& path) const {
        const bool neutral = j.contains("world_matrix");
        for (const auto& [key, value] : j.items()) {
            if (isNoteKey(key) || contains(kDecalNotes, key)) continue;
            if (neutral && contains(kWorldMatrixNotes, key)) continue;
            if (!contains(kDecalKeys, key)) fail(keyPath(path, key), unknownKeyMessage(key, kDecalKeys));
        }
    }

    // Key of "textures" first; otherwise a string with '.' or '/' is an image path.
    TextureSetRequest textureReference(const json& j, const std::string& path) const {
        const json& t = j.at("texture");
        const std::string tpath = path + ".texture";
        if (t.is_object()) return parseTexture(t, tpath);
        if (!t.is_string()) fail(tpath, "expected a texture name, an image path or a texture object");
        const std::string name = t.get<std::string>();
        if (auto it = textureTable_.find(name); it != textureTable_.end()) return it->second;
        if (name.find_first_of("./") != std::string::npos) {
            TextureSetRequest set;
            set.albedo = imageRequest(name, tpath);
            return set;
        }
        fail(tpath, fmt::format("unknown texture '{}' (not a key of 'textures' and not a file name)", name));
    }

    float opacity(const json& v, const std::string& path) const {
        if (!v.is_number() || !(v.get<double>() >= 0.0 && v.get<double>() <= 1.0))
            fail(path, "expected a number in [0,1]");
        return float(v.get<double>());
    }

    int priority(const json& v, const std::string& path) const {
        if (!v.is_number_integer()) fail(path, "expected an integer");
        const bool inRange = v.is_number_unsigned()
                                 ? v.get<std::uint64_t>() <= std::uint64_t(INT_MAX)
                                 : v.get<std::int64_t>() >= INT_MIN && v.get<std::int64_t>() <= INT_MAX;
        if (!inRange) fail(path, "integer out of range");
        return int(v.get<std::int64_t>());
    }

    // Exactly one of: matrix (or world_matrix), translate/rotate/scale, look-at.
    glm::dmat4 placement(const json& j, const std::string& path) const {
        const bool hasMatrix = j.contains("matrix"), hasWorld = j.contains("world_matrix");
        if (hasMatrix && hasWorld) fail(path, "give either 'matrix' or 'world_matrix', not both");
        std::vector<std::string> groups;  // one representative key per placement style found
        if (hasMatrix || hasWorld) groups.push_back(hasMatrix ? "matrix" : "world_matrix");
        for (const std::string& k : kTrsKeys)
            if (j.contains(k) && !(hasWorld && k == "scale")) {
                groups.push_back(k);
                break;
            }
        for (const std::string& k : kLookAtKeys)
            if (j.contains(k)) {
                groups.push_back(k);
                break;
            }
        if (groups.empty())
            fail(path,
                 "missing placement (give 'matrix', translate/rotate_deg/quaternion_wxyz/scale, or "
                 "origin/target/up/size)");
        if (groups.size() > 1)
            fail(path, fmt::format("conflicting placements '{}' and '{}' (give one of: matrix, "
                                   "translate/rotate_deg/quaternion_wxyz/scale, origin/target/up/size)",
                                   groups[0], groups[1]));
        if (hasMatrix || hasWorld) {
            const std::string key = hasMatrix ? "matrix" : "world_matrix";
            return matrixPlacement(j.at(key), path + "." + key);
        }
        if (contains(kTrsKeys, groups[0])) return trsPlacement(j, path);
        return lookAtPlacement(j, path);
    }

    void requireInvertible(const glm::dmat4& m, const std::string& path) const {
        if (!isInvertibleDecalMatrix(m)) fail(path, "not invertible (degenerate decal)");
    }

    glm::dmat4 matrixPlacement(const json& v, const std::string& path) const {
        const char* shape = "expected 4 rows of 4 numbers (row-major, translation in the last column)";
        if (!v.is_array() || v.size() != 4) fail(path, shape);
        double rows[4][4];
        for (size_t r = 0; r < 4; ++r) {
            if (!v[r].is_array() || v[r].size() != 4) fail(path, shape);
            for (size_t c = 0; c < 4; ++c) rows[r][c] = number(v[r][c], indexPath(indexPath(path, r), c));
        }
        if (rows[3][0] != 0.0 || rows[3][1] != 0.0 || rows[3][2] != 0.0 || rows[3][3] != 1.0)
            fail(path, "last row must be [0, 0, 0, 1] (affine)");
        const glm::dmat4 m = scene_detail::matrixFromRows(rows);
        requireInvertible(m, path);
        return m;
    }

    glm::dmat4 trsPlacement(const json& j, const std::string& path) const {
        const glm::dvec3 t = j.contains("translate") ? vec3(j.at("translate"), path + ".translate") : glm::dvec3(0.0);
        if (j.contains("rotate_deg") && j.contains("quaternion_wxyz"))
            fail(path, "give either 'rotate_deg' or 'quaternion_wxyz', not both");
        glm::dmat3 r(1.0);
        if (j.contains("rotate_deg"))
            r = scene_detail::rotationFromEulerXyzDegrees(vec3(j.at("rotate_deg"), path + ".rotate_deg"));
        if (j.contains("quaternion_wxyz")) r = quaternion(j.at("quaternion_wxyz"), path + ".quaternion_wxyz");
        const std::string spath = path + ".scale";
        const glm::dvec3 s = j.contains("scale") ? vec3OrScalar(j.at("scale"), spath) : glm::dvec3(1.0);
        const glm::dmat4 m = composeTrs(t, r, s);
        requireInvertible(m, j.contains("scale") ? spath : path);
        return m;
    }

    glm::dmat3 quaternion(const json& v, const std::string& path) const {
        if (!v.is_array() || v.size() != 4) fail(path, "expected 4 numbers (w, x, y, z)");
        double q[4];
        for (size_t i = 0; i < 4; ++i) q[i] = number(v[i], indexPath(path, i));
        const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(norm > 1e-12) || !std::isfinite(norm)) fail(path, "zero quaternion (no rotation defined)");
        return scene_detail::rotationFromQuaternion(q[0], q[1], q[2], q[3]);
    }

    glm::dmat4 lookAtPlacement(const json& j, const std::string& path) const {
        for (const std::string& k : kLookAtKeys)
            if (!j.contains(k))
                fail(path,
                     fmt::format("look-at placement needs 'origin', 'target', 'up' and 'size' (missing '{}')", k));
        const glm::dvec3 origin = vec3(j.at("origin"), path + ".origin");
        const glm::dvec3 target = vec3(j.at("target"), path + ".target");
        const glm::dvec3 up = vec3(j.at("up"), path + ".up");
        const glm::dvec3 size = vec3OrScalar(j.at("size"), path + ".size");
        const glm::dvec3 view = target - origin;
        const double viewLength = glm::length(view);
        if (!(viewLength > 1e-12 * std::max(1.0, glm::length(origin))))
            fail(path + ".target", "equals 'origin' (no view direction)");
        if (!(glm::length(glm::cross(up, view)) > 1e-9 * glm::length(up) * viewLength))
            fail(path + ".up", "zero or parallel to the view direction (origin -> target)");
        if (!(size.x > 0.0 && size.y > 0.0 && size.z > 0.0))
            fail(path + ".size", "expected positive sizes (width, height, depth)");
        const glm::dmat4 m = scene_detail::lookAtBox(origin, target, up, size);
        requireInvertible(m, path + ".size");
        return m;
    }

    // Same file with the same alpha mode -> one decoded texture shared by index.
    int textureIndex(const TextureRequest& request, DecalScene& scene) {
        fs::path file(request.file);
        if (file.is_relative()) file = dir_ / file;
        std::error_code ec;
        fs::path identity = fs::weakly_canonical(file, ec);
        if (ec) identity = file.lexically_normal();
        std::string files = identity.string();
        for (std::size_t f = 1; f < request.faces.size(); ++f) files += "|" + request.faces[f];  // a cube is all six
        const auto key = std::make_tuple(files, request.alpha, request.layout, request.content, request.flip_green);
        if (auto it = loaded_.find(key); it != loaded_.end()) return it->second;
        try {
            if (request.layout == scene_detail::TextureLayout::CubeFaces) {
                std::vector<Texture2D> faces;
                for (const std::string& face : request.faces) {
                    fs::path face_file(face);
                    if (face_file.is_relative()) face_file = dir_ / face_file;
                    faces.push_back(loadTexture2D(face_file.string(), request.alpha, request.content));
                }
                scene.textures.push_back(cubeFromFaces(faces));
            } else {
                scene.textures.push_back(scene_detail::arrangeTexture(
                    loadTexture2D(file.string(), request.alpha, request.content), request.layout));
            }
            if (request.flip_green) flipGreen(scene.textures.back());
        } catch (const Error& e) {
            fail(request.jsonPath, e.what());
        }
        const int index = int(scene.textures.size()) - 1;
        loaded_.emplace(key, index);
        return index;
    }
};

}  // namespace

DecalScene loadScene(const std::string& path) { return SceneParser(path).load(); }

}  // namespace decalcomp
