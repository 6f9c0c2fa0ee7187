#include "decalcomp/provenance.hpp"

#include <fmt/format.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <cstdint>
#include <nlohmann/json.hpp>

#include "decalcomp/error.hpp"
#include "decalcomp/version.hpp"

namespace decalcomp {

namespace {

constexpr const char* kVersionAttribute = "decalcomp/version";
constexpr const char* kSceneAttribute = "decalcomp/scene";
constexpr const char* kSceneFileAttribute = "decalcomp/sceneFile";
constexpr const char* kDecalsAttribute = "decalcomp/decals";
constexpr const char* kScenesAttribute = "decalcomp/scenes";

std::optional<std::string> stringAttribute(const Imf::Header& header, const char* name, const std::string& file) {
    const auto found = header.find(name);
    if (found == header.end()) return std::nullopt;
    const auto* text = dynamic_cast<const Imf::StringAttribute*>(&found.attribute());
    if (!text)
        throw inputError(fmt::format("{}: header attribute {}: a {}, expected a string", file, name, found.attribute().typeName()));
    return text->value();
}

std::vector<std::string> stringArray(const std::string& value, const char* name, const std::string& file) {
    const nlohmann::json doc = nlohmann::json::parse(value, nullptr, false);
    if (!doc.is_array()) throw inputError(fmt::format("{}: header attribute {}: expected a JSON array of strings", file, name));
    std::vector<std::string> result;
    for (const auto& item : doc) {
        if (!item.is_string()) throw inputError(fmt::format("{}: header attribute {}: expected a JSON array of strings", file, name));
        result.push_back(item.get<std::string>());
    }
    return result;
}

}  // namespace

std::string sceneFingerprint(const std::string& canonical_json) {
    std::uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a offset basis and prime (64 bit)
    for (unsigned char c : canonical_json) hash = (hash ^ c) * 0x100000001b3ull;
    return fmt::format("fnv1a64:{:016x}", hash);
}

std::optional<ProvenanceRecord> readProvenance(const Imf::Header& header, const std::string& file) {
    const auto scene = stringAttribute(header, kSceneAttribute, file);
    if (!scene) return std::nullopt;
    ProvenanceRecord record;
    record.scene = *scene;
    record.version = stringAttribute(header, kVersionAttribute, file).value_or("");
    record.scene_file = stringAttribute(header, kSceneFileAttribute, file).value_or("");
    if (const auto decals = stringAttribute(header, kDecalsAttribute, file)) record.decals = stringArray(*decals, kDecalsAttribute, file);
    if (const auto scenes = stringAttribute(header, kScenesAttribute, file)) record.scenes = stringArray(*scenes, kScenesAttribute, file);
    if (record.scenes.empty() || record.scenes.back() != record.scene) record.scenes.push_back(record.scene);
    return record;
}

ProvenanceRecord composeProvenance(const DecalScene& scene, const std::vector<Decal>& decals,
                                   const std::optional<ProvenanceRecord>& previous) {
    ProvenanceRecord record;
    record.version = decalcomp::kVersion;
    record.scene = scene.fingerprint.empty() ? "in code" : scene.fingerprint;
    record.scene_file = scene.source;
    for (const Decal& decal : decals) record.decals.push_back(decal.name);
    if (previous) record.scenes = previous->scenes;
    record.scenes.push_back(record.scene);
    return record;
}

std::map<std::string, std::string> provenanceAttributes(const ProvenanceRecord& record) {
    return {{kVersionAttribute, record.version},
            {kSceneAttribute, record.scene},
            {kSceneFileAttribute, record.scene_file},
            {kDecalsAttribute, nlohmann::json(record.decals).dump()},
            {kScenesAttribute, nlohmann::json(record.scenes).dump()}};
}

}  // namespace decalcomp
