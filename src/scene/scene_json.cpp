// Scene files (docs/scene-format.md): JSON -> validated DecalScene with decoded textures.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "decalcomp/provenance.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/json_fields.hpp"
#include "decalcomp/scene.hpp"
#include "decalcomp/textures.hpp"
#include "scene/animation_json.hpp"
#include "scene/colour_json.hpp"
#include "scene/kind_json.hpp"
#include "scene/mask_json.hpp"
#include "scene/material_json.hpp"
#include "scene/placement.hpp"
#include "scene/texture_space_json.hpp"

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
const std::vector<std::string> kTextureSetKeys = {"albedo", "volume", "cube",     "cube_faces", "normal",
                                                  "orm",    "emission", "alpha", "normal_y", "colorspace"};
// Keys of one map written as an object instead of a path.
const std::vector<std::string> kMapKeys = {"file", "colorspace"};
// Single-channel maps users may expect; the format packs them into "orm".
const std::vector<std::string> kPackedIntoOrm = {"roughness", "metallic", "occlusion", "ao"};

bool contains(const std::vector<std::string>& list, const std::string& s) {
    return std::find(list.begin(), list.end(), s) != list.end();
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
    std::optional<JsonField> colorspace;  // the map's own, else its set's (colour maps only)
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

struct ParsedDecal {
    Decal decal;
    TextureSetRequest texture;
    int priority = 0;
    std::string path;  // its JSON path, for errors found after parsing
};

class SceneParser {
public:
    // `file` names the scene in messages; relative texture and mesh paths resolve against `dir`.
    SceneParser(std::string file, fs::path dir, SceneOptions options)
        : file_(std::move(file)), dir_(std::move(dir)), options_(std::move(options)) {
        meshes_.dir = dir_;
    }

    DecalScene load(const json& doc) {
        const JsonField root(doc, file_);
        root.requireObject("a JSON object with a 'decals' array");
        checkTopLevelKeys(root);
        colour_.emplace(root, options_.ocio_config);
        const TextureFilter defaultFilter = parseDefaultFilter(root);
        parseTextureTable(root);
        const JsonField decals = root.required("decals", "an array of decals");
        decals.requireArray("an array of decals");

        // Validate every decal before decoding any texture, so a typo fails fast.
        std::vector<ParsedDecal> parsed;
        for (const JsonField& decal : decals.elements()) parsed.push_back(parseDecal(decal, defaultFilter));

        DecalScene scene;
        scene.masks = masks_;
        scene.meshes = std::move(meshes_.meshes);

        scene.warnings = duplicateNameWarnings(decals);
        for (const RestMesh& mesh : scene.meshes)
            if (mesh.overlapping_uv_triangles > 0)
                scene.warnings.push_back(fmt::format(
                    "{}: {} of its {} triangles overlap others in UV space: a UV there names two surface points, so "
                    "texture-space decals may show up twice; give the mesh non-overlapping UVs",
                    mesh.source, mesh.overlapping_uv_triangles, mesh.triangles.size()));
        for (ParsedDecal& p : parsed) {
            auto index = [&](const std::optional<TextureRequest>& r) { return r ? textureIndex(*r, scene) : -1; };
            p.decal.albedo_texture = index(p.texture.albedo);
            p.decal.normal_texture = index(p.texture.normal);
            p.decal.orm_texture = index(p.texture.orm);
            p.decal.emission_texture = index(p.texture.emission);
            attachBake(p, scene);
        }
        // Lower priority blends first; equal priorities keep file order (stable).
        std::stable_sort(parsed.begin(), parsed.end(),
                         [](const ParsedDecal& a, const ParsedDecal& b) { return a.priority < b.priority; });
        for (ParsedDecal& p : parsed) scene.decals.push_back(std::move(p.decal));
        scene.working_space = colour_->workingSpace();
        scene.colour_config = colour_->configFile();
        return scene;
    }

private:
    // Names identify decals in reports, so two decals of one name are probably a copy-paste slip.
    std::vector<std::string> duplicateNameWarnings(const JsonField& decals) const {
        std::vector<std::string> warnings;
        std::map<std::string, std::string> first_path;  // name -> the decal that has it first
        for (const JsonField& decal : decals.elements()) {
            const auto name = decal.optionalString("name");
            if (!name) continue;
            const auto [it, inserted] = first_path.emplace(*name, decal.path());
            if (!inserted)
                warnings.push_back(fmt::format("{}: {}.name: '{}' is also the name of {}; give each decal its own name "
                                               "so reports and warnings can tell them apart",
                                               file_, decal.path(), *name, it->second));
        }
        return warnings;
    }

    std::string file_;
    fs::path dir_;
    SceneOptions options_;
    std::optional<scene_detail::SceneColour> colour_;
    std::map<std::string, TextureSetRequest> textureTable_;
    // decoded textures by (files, alpha, layout, content, flip, colour spaces) -> texture index
    std::map<std::tuple<std::string, AlphaMode, scene_detail::TextureLayout, TextureContent, bool, std::string>, int>
        loaded_;
    mutable std::vector<DecalMask> masks_;  // distinct masks, filled while parsing decals
    mutable scene_detail::MeshTable meshes_;  // rest meshes of texture-space decals, each file once

    // Unknown top-level keys are descriptive notes (the neutral format has many); only near
    // misspellings of real keys are errors, since "decal" for "decals" must not pass silently.
    void checkTopLevelKeys(const JsonField& root) const {
        for (const auto& [key, value] : root.members())
            if (!contains(kTopLevelKeys, key) && !contains(scene_detail::kColourTopLevelKeys, key) &&
                !JsonField::isNoteKey(key) && closestJsonKey(key, kTopLevelKeys))
                root.failUnknownKey(key, kTopLevelKeys);
        if (const auto format = root.optional("format")) format->string();  // must be a string
    }

    static TextureFilter parseFilter(const JsonField& v) {
        return v.choice(std::array{TextureFilter::Nearest, TextureFilter::Linear, TextureFilter::Mip}, textureFilterName);
    }

    // Top-level "filter", or the neutral format's "interpolation" (Cycles names), sets the default.
    static TextureFilter parseDefaultFilter(const JsonField& root) {
        const auto filter = root.optional("filter"), interpolation = root.optional("interpolation");
        if (filter && interpolation) interpolation->fail("give either 'filter' or 'interpolation', not both");
        if (filter) return parseFilter(*filter);
        if (!interpolation) return TextureFilter::Linear;
        return interpolation->choice({"closest", "linear"}) == 0 ? TextureFilter::Nearest : TextureFilter::Linear;
    }

    void parseTextureTable(const JsonField& root) {
        const auto table = root.optional("textures");
        if (!table) return;
        table->requireObject("an object mapping names to textures");
        for (const auto& [name, value] : table->members()) textureTable_[name] = parseTexture(value);
    }

    // A map: an image path, or {"file": path, "colorspace": name}.
    static TextureRequest imageRequest(const JsonField& v) {
        TextureRequest request;
        request.jsonPath = v.path();
        if (v.isObject()) {
            v.checkKeys(kMapKeys);
            request.file = v.required("file", "the image path").nonEmptyString("image path");
            request.colorspace = v.optional("colorspace");
            return request;
        }
        request.file = v.nonEmptyString("image path");
        return request;
    }

    // "file.png" is shorthand for {"albedo": "file.png"}.
    static TextureSetRequest parseTexture(const JsonField& v) {
        TextureSetRequest set;
        if (v.value().is_string()) {
            set.albedo = imageRequest(v);
            return set;
        }
        v.requireObject("an image path or an object like {\"albedo\": \"file.png\"}");
        AlphaMode alpha = AlphaMode::Auto;
        bool normal_y_down = false;
        std::optional<JsonField> colorspace;  // the set's, for its colour maps
        for (const auto& [key, value] : v.members()) {
            if (key == "albedo" || key == "volume" || key == "cube") {
                if (set.albedo) value.fail("give one of 'albedo', 'volume', 'cube', 'cube_faces'");
                set.albedo = imageRequest(value);
                set.albedo->layout = key == "volume" ? scene_detail::TextureLayout::VolumeStrip
                                     : key == "cube" ? scene_detail::TextureLayout::CubeStrip
                                                     : scene_detail::TextureLayout::Image;
            } else if (key == "cube_faces") {
                if (set.albedo) value.fail("give one of 'albedo', 'volume', 'cube', 'cube_faces'");
                value.requireArray("6 image paths (+X,-X,+Y,-Y,+Z,-Z)", 6);
                TextureRequest request;
                for (const JsonField& face : value.elements()) request.faces.push_back(face.nonEmptyString("image path"));
                request.file = request.faces[0];
                request.jsonPath = value.path();
                request.layout = scene_detail::TextureLayout::CubeFaces;
                set.albedo = request;
            } else if (key == "normal" || key == "orm" || key == "emission") {
                // same layout as the albedo's kind (a strip for volumes and cubes); normal and ORM are data
                TextureRequest request = imageRequest(value);
                if (key != "emission") request.content = TextureContent::Data;
                (key == "normal" ? set.normal : key == "orm" ? set.orm : set.emission) = request;
            } else if (key == "alpha") {
                alpha = std::array{AlphaMode::Auto, AlphaMode::Straight,
                                   AlphaMode::Premultiplied}[value.choice({"auto", "straight", "premultiplied"})];
            } else if (key == "colorspace") {
                value.nonEmptyString("colour space name");
                colorspace = value;
            } else if (key == "normal_y") {
                normal_y_down = value.choice({"up", "down"}) == 1;  // up: OpenGL, down: DirectX
            } else if (contains(kPackedIntoOrm, key)) {
                value.fail("not a map of its own: pack occlusion, roughness and metallic into 'orm' (R, G, B)");
            } else if (!JsonField::isNoteKey(key)) {
                v.failUnknownKey(key, kTextureSetKeys);
            }
        }
        if (set.empty()) v.fail("expected at least one map: albedo (or volume, cube, cube_faces), normal, orm, emission");
        if (normal_y_down && !set.normal) v.required("normal_y").fail("there is no 'normal' map to flip");
        if (set.normal) set.normal->flip_green = normal_y_down;
        for (auto* r : {&set.albedo, &set.normal, &set.orm, &set.emission})
            if (*r) (*r)->alpha = alpha;
        for (auto* r : {&set.normal, &set.orm})  // data, not colour: converting would change the values
            if (*r && (*r)->colorspace)
                (*r)->colorspace->fail("normal and orm maps hold data, not colour: they are never converted "
                                       "(leave out 'colorspace')");
        for (auto* r : {&set.albedo, &set.emission})
            if (*r && !(*r)->colorspace) (*r)->colorspace = colorspace;
        if (colorspace && !set.albedo && !set.emission)
            colorspace->fail("there is no colour map (albedo or emission) to apply it to");
        return set;
    }

    ParsedDecal parseDecal(const JsonField& j, TextureFilter defaultFilter) const {
        j.requireObject("an object");
        // Kind first: fields of future kinds should read as "unsupported kind", not "unknown key".
        ParsedDecal p;
        p.path = j.path();
        if (const auto kind = j.optional("kind")) {
            const auto known = scene_detail::kindFromName(kind->string());
            if (!known)
                kind->fail(fmt::format("unsupported kind '{}' (supported: box, volume, frustum, cube)", kind->string()));
            p.decal.kind = *known;
        }
        checkDecalKeys(j);
        p.decal.name = j.optionalString("name").value_or(j.path());
        if (const auto texture = j.optional("texture")) p.texture = textureReference(*texture);
        if (!scene_detail::parseDecalAnimation(j, [this](const JsonField& v) { return placement(v); }, p.decal))
            p.decal.world_matrix = scene_detail::isProjectorLookAt(j, p.decal.kind) ? scene_detail::projectorLookAt(j)
                                                                                    : placement(j);
        scene_detail::parseKindFields(j, p.decal);
        for (auto* r : {&p.texture.albedo, &p.texture.normal, &p.texture.orm, &p.texture.emission})
            if (*r) (*r)->layout = scene_detail::layoutForKind(p.decal.kind, (*r)->layout, (*r)->jsonPath, file_);
        if (const auto affects = j.optional("affects")) {
            scene_detail::parseAffects(*affects, p.decal);
            checkAffectedTargetsHaveValues(p, *affects);
        }
        if (p.texture.empty() && !std::any_of(p.decal.effects.begin(), p.decal.effects.end(), [](const TargetEffect& e) {
                return e.value.has_value() && e.factor > 0.0f;
            }))
            j.fail("missing 'texture' (a decal needs a texture set, or constant values in 'affects')");
        if (const auto opacity = j.optional("opacity")) p.decal.opacity = float(opacity->numberIn(0.0, 1.0));
        p.decal.filter = j.has("filter") ? parseFilter(j.required("filter")) : defaultFilter;
        p.priority = j.optionalInteger("priority").value_or(0);
        if (const auto mask = j.optional("mask"))  // identical masks share one entry of DecalScene::masks
            p.decal.mask = scene_detail::parseAndInternMask(*mask, masks_);
        scene_detail::parseDecalSpace(j, p.decal, meshes_, masks_);
        return p;
    }

    // Bake mode (docs/texture-space.md "Bake mode"): no normal maps; a reused "baked" file's layers
    // join the textures and the decal reads them.
    void attachBake(ParsedDecal& p, DecalScene& scene) const {
        if (p.decal.space != DecalSpace::ObjectRest || p.decal.rest_mode != RestMode::Bake) return;
        if (decalAffects(p.decal, DecalTarget::Normal))
            throw jsonFieldError(file_, p.path + ".mode",
                                 "bake mode does not carry normal maps (the bake holds colours, not the surface's "
                                 "frame); use \"exact\" for this decal");
        const auto file = meshes_.baked_files.find(p.decal.bake_slot);
        if (file == meshes_.baked_files.end()) return;
        BakedLayers& layers = file->second;
        auto add = [&](std::optional<Texture2D>& layer, bool wanted, const char* name) {
            if (!wanted) return -1;
            if (!layer)
                throw jsonFieldError(file_, p.path + ".baked",
                                     fmt::format("the baked file has no {} layer, which this decal writes; re-run "
                                                 "decalcomp bake",
                                                 name));
            scene.textures.push_back(std::move(*layer));
            return int(scene.textures.size()) - 1;
        };
        std::optional<Texture2D> albedo(std::move(layers.albedo));
        const int a = add(albedo, true, "albedo");
        const int orm = add(layers.orm,
                            decalAffects(p.decal, DecalTarget::Roughness) || decalAffects(p.decal, DecalTarget::Metallic) ||
                                decalAffects(p.decal, DecalTarget::AmbientOcclusion),
                            "orm");
        const int emission = add(layers.emission, decalAffects(p.decal, DecalTarget::Emission), "emission");
        p.decal = bakedDecal(p.decal, a, orm, emission);
    }

    // A listed target with neither a map nor a constant would silently do nothing: a mistake.
    static void checkAffectedTargetsHaveValues(const ParsedDecal& p, const JsonField& affects) {
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
            affects.required(decalTargetName(target))
                .fail(target == DecalTarget::Normal
                          ? std::string("nothing to write: the texture set has no 'normal' map")
                          : fmt::format("nothing to write: the texture set has no '{}' map and there is no 'value'", map));
        }
    }

    static void checkDecalKeys(const JsonField& j) {
        const bool neutral = j.has("world_matrix");
        for (const auto& [key, value] : j.members()) {
            if (JsonField::isNoteKey(key) || contains(kDecalNotes, key)) continue;
            if (neutral && contains(kWorldMatrixNotes, key)) continue;
            if (contains(scene_detail::kTextureSpaceKeys, key) || contains(scene_detail::kTextureSpaceNotes, key))
                continue;
            if (!contains(kDecalKeys, key)) j.failUnknownKey(key, kDecalKeys);
        }
    }

    // Key of "textures" first; otherwise a string with '.' or '/' is an image path.
    TextureSetRequest textureReference(const JsonField& t) const {
        if (t.isObject()) return parseTexture(t);
        if (!t.value().is_string()) t.fail("expected a texture name, an image path or a texture object");
        const std::string name = t.string();
        if (auto it = textureTable_.find(name); it != textureTable_.end()) return it->second;
        if (name.find_first_of("./") != std::string::npos) {
            TextureSetRequest set;
            set.albedo = imageRequest(t);
            return set;
        }
        t.fail(fmt::format("unknown texture '{}' (not a key of 'textures' and not a file name)", name));
    }

    // Exactly one of: matrix (or world_matrix), translate/rotate/scale, look-at.
    glm::dmat4 placement(const JsonField& j) const {
        const bool hasMatrix = j.has("matrix"), hasWorld = j.has("world_matrix");
        if (hasMatrix && hasWorld) j.fail("give either 'matrix' or 'world_matrix', not both");
        // The neutral exports restate the matrix's scale beside it (world decals' world_matrix,
        // rest-pose decals' matrix): a note there, not a second placement.
        const bool restSpace = j.has("space") && j.required("space").value() == "object_rest";
        const bool scaleIsNote = hasWorld || (hasMatrix && restSpace);
        std::vector<std::string> groups;  // one representative key per placement style found
        if (hasMatrix || hasWorld) groups.push_back(hasMatrix ? "matrix" : "world_matrix");
        for (const std::string& k : kTrsKeys)
            if (j.has(k) && !(scaleIsNote && k == "scale")) {
                groups.push_back(k);
                break;
            }
        for (const std::string& k : kLookAtKeys)
            if (j.has(k)) {
                groups.push_back(k);
                break;
            }
        if (groups.empty())
            j.fail("missing placement (give 'matrix', translate/rotate_deg/quaternion_wxyz/scale, or "
                   "origin/target/up/size)");
        if (groups.size() > 1)
            j.fail(fmt::format("conflicting placements '{}' and '{}' (give one of: matrix, "
                               "translate/rotate_deg/quaternion_wxyz/scale, origin/target/up/size)",
                               groups[0], groups[1]));
        if (hasMatrix || hasWorld) return matrixPlacement(j.required(hasMatrix ? "matrix" : "world_matrix"));
        if (contains(kTrsKeys, groups[0])) return trsPlacement(j);
        return lookAtPlacement(j);
    }

    static void requireInvertible(const glm::dmat4& m, const JsonField& at) {
        if (!isInvertibleDecalMatrix(m)) at.fail("not invertible (degenerate decal)");
    }

    static glm::dmat4 matrixPlacement(const JsonField& v) {
        const glm::dmat4 m = v.matrix4();
        if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)  // GLM: m[col][row]
            v.fail("last row must be [0, 0, 0, 1] (affine)");
        requireInvertible(m, v);
        return m;
    }

    static glm::dmat4 trsPlacement(const JsonField& j) {
        const glm::dvec3 t = j.optionalVec3("translate").value_or(glm::dvec3(0.0));
        if (j.has("rotate_deg") && j.has("quaternion_wxyz")) j.fail("give either 'rotate_deg' or 'quaternion_wxyz', not both");
        glm::dmat3 r(1.0);
        if (const auto euler = j.optionalVec3("rotate_deg")) r = scene_detail::rotationFromEulerXyzDegrees(*euler);
        if (const auto q = j.optional("quaternion_wxyz")) r = quaternion(*q);
        const auto scale = j.optional("scale");
        const glm::dmat4 m = composeTrs(t, r, scale ? scale->vec3OrScalar() : glm::dvec3(1.0));
        requireInvertible(m, scale ? *scale : j);
        return m;
    }

    static glm::dmat3 quaternion(const JsonField& v) {
        v.requireArray("4 numbers (w, x, y, z)", 4);
        double q[4];
        for (size_t i = 0; i < 4; ++i) q[i] = v[i].number();
        const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(norm > 1e-12) || !std::isfinite(norm)) v.fail("zero quaternion (no rotation defined)");
        return scene_detail::rotationFromQuaternion(q[0], q[1], q[2], q[3]);
    }

    static glm::dmat4 lookAtPlacement(const JsonField& j) {
        for (const std::string& k : kLookAtKeys)
            if (!j.has(k))
                j.fail(fmt::format("look-at placement needs 'origin', 'target', 'up' and 'size' (missing '{}')", k));
        const glm::dvec3 origin = j.required("origin").vec3();
        const glm::dvec3 target = j.required("target").vec3();
        const glm::dvec3 up = j.required("up").vec3();
        const JsonField sizeField = j.required("size");
        const glm::dvec3 size = sizeField.vec3OrScalar();
        const glm::dvec3 view = target - origin;
        const double viewLength = glm::length(view);
        if (!(viewLength > 1e-12 * std::max(1.0, glm::length(origin))))
            j.required("target").fail("equals 'origin' (no view direction)");
        if (!(glm::length(glm::cross(up, view)) > 1e-9 * glm::length(up) * viewLength))
            j.required("up").fail("zero or parallel to the view direction (origin -> target)");
        if (!(size.x > 0.0 && size.y > 0.0 && size.z > 0.0)) sizeField.fail("expected positive sizes (width, height, depth)");
        const glm::dmat4 m = scene_detail::lookAtBox(origin, target, up, size);
        requireInvertible(m, sizeField);
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
        const std::optional<TextureColour> colour =
            request.content == TextureContent::Colour ? colour_->forTexture(request.colorspace) : std::nullopt;
        const TextureColour* decode = colour ? &*colour : nullptr;
        const std::string spaces =
            colour ? colour->integer_space + "|" + colour->float_space + "|" + colour->working_space : "";
        const auto key =
            std::make_tuple(files, request.alpha, request.layout, request.content, request.flip_green, spaces);
        if (auto it = loaded_.find(key); it != loaded_.end()) return it->second;
        try {
            if (request.layout == scene_detail::TextureLayout::CubeFaces) {
                std::vector<Texture2D> faces;
                for (const std::string& face : request.faces) {
                    fs::path face_file(face);
                    if (face_file.is_relative()) face_file = dir_ / face_file;
                    faces.push_back(loadTexture2D(face_file.string(), request.alpha, request.content, decode));
                }
                scene.textures.push_back(cubeFromFaces(faces));
            } else {
                scene.textures.push_back(scene_detail::arrangeTexture(
                    loadTexture2D(file.string(), request.alpha, request.content, decode), request.layout));
            }
            if (request.flip_green) flipGreen(scene.textures.back());
        } catch (const Error& e) {
            throw jsonFieldError(file_, request.jsonPath, e.what());
        }
        const int index = int(scene.textures.size()) - 1;
        loaded_.emplace(key, index);
        return index;
    }
};

}  // namespace

DecalScene loadScene(const std::string& path, const SceneOptions& options) {
    const json doc = readJsonFile(path, "scene file");
    DecalScene scene = SceneParser(path, fs::path(path).parent_path(), options).load(doc);
    scene.source = path;
    scene.fingerprint = sceneFingerprint(doc.dump());
    return scene;
}

DecalScene parseScene(const std::string& json_text, const std::string& label, const std::string& base_dir,
                      const SceneOptions& options) {
    const json doc = parseJsonText(json_text, label);
    DecalScene scene = SceneParser(label, base_dir, options).load(doc);
    scene.source = label;
    scene.fingerprint = sceneFingerprint(doc.dump());
    return scene;
}

}  // namespace decalcomp
