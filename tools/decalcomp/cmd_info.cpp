#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.hpp"
#include "decalcomp/provenance.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/cryptomatte.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/frame_beauty.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/sequence_conventions.hpp"

namespace decalcomp::cli {

namespace {

struct InfoFlags {
    std::vector<std::string> inputs, passes;
    std::string camera;
    MappingOptions mapping;
    std::vector<std::string> channels;
    std::string depth;
    bool json = false;
};

const char* typeName(SampleType t) {
    switch (t) {
        case SampleType::Uint: return "uint";
        case SampleType::Half: return "half";
        case SampleType::Float: return "float";
    }
    return "?";
}

// `info` writes text for people and, with --json, one JSON document with the same content for
// scripts. Every section fills both: `out` is std::cout, or a stream that drops the text.
struct InfoOutput {
    std::ostream& out;
    nlohmann::ordered_json& doc;
};

nlohmann::json matrixJson(const glm::dmat4& m) {
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});  // row-major, as sidecars
    return rows;
}

void printMatrix(std::ostream& out, const std::string& title, const glm::dmat4& m) {
    out << "  " << title << ":\n";
    for (int r = 0; r < 4; ++r) out << fmt::format("    [{:12.6f} {:12.6f} {:12.6f} {:12.6f}]\n", m[0][r], m[1][r], m[2][r], m[3][r]);
}

std::string windowText(const Imath::Box2i& w) {
    return fmt::format("({},{})-({},{})", w.min.x, w.min.y, w.max.x, w.max.y);
}

nlohmann::json windowJson(const Imath::Box2i& w) { return {w.min.x, w.min.y, w.max.x, w.max.y}; }

nlohmann::ordered_json provenanceJson(const ProvenanceRecord& record) {
    return {{"version", record.version}, {"scene", record.scene}, {"scene_file", record.scene_file},
            {"decals", record.decals},   {"scenes", record.scenes}};
}

void printFile(const InfoOutput& o, const ExrImage& image) {
    nlohmann::ordered_json file = {{"path", image.path}, {"parts", nlohmann::json::array()}};
    o.out << image.path << ": " << image.parts.size() << " part(s)\n";
    for (std::size_t p = 0; p < image.parts.size(); ++p) {
        const ExrPart& part = image.parts[p];
        const Imath::Box2i dw = part.header.dataWindow(), display = part.header.displayWindow();
        const std::string name = part.header.hasName() ? part.header.name() : "";
        o.out << fmt::format("part {} '{}': {}x{} data window {}{}, {} channels\n", p, name, part.width, part.height,
                             windowText(dw), dw == display ? "" : " (display window " + windowText(display) + ")",
                             part.channels.size());
        nlohmann::ordered_json channels = nlohmann::json::array();
        for (const ExrChannel& c : part.channels) {
            o.out << fmt::format("  {} ({})\n", c.qualified, typeName(c.type));
            channels.push_back({{"name", c.qualified}, {"type", typeName(c.type)}});
        }
        file["parts"].push_back({{"name", name}, {"width", part.width}, {"height", part.height},
                                 {"data_window", windowJson(dw)}, {"display_window", windowJson(display)},
                                 {"channels", channels}});
    }
    const auto record = readProvenance(image.parts.front().header, image.path);
    file["provenance"] = record ? provenanceJson(*record) : nlohmann::ordered_json();
    if (record) {
        o.out << fmt::format("composited by decalcomp {} with {} ({}): {} decal(s){}{}\n", record->version,
                             record->scene_file.empty() ? "a scene built in code" : record->scene_file, record->scene,
                             record->decals.size(), record->decals.empty() ? "" : ": ", fmt::join(record->decals, ", "));
        if (record->scenes.size() > 1)
            o.out << fmt::format("  scenes composited into it, oldest first: {}\n", fmt::join(record->scenes, ", "));
    }
    o.doc["files"].push_back(file);
}

// Each Cryptomatte layer: where it is, its hash and manifest, and the names it knows (text: the
// first kShownNames; JSON: all). Masks select by these names (docs/scene-format.md).
void printCryptomatte(const InfoOutput& o, const std::vector<ExrImage>& files) {
    constexpr std::size_t kShownNames = 24;
    const std::vector<CryptomatteLayer> layers = cryptomatteLayers(files);
    o.doc["cryptomatte"] = nlohmann::json::array();
    if (layers.empty()) return;
    o.out << "cryptomatte: " << layers.size() << " layer(s)\n";
    for (const CryptomatteLayer& layer : layers) {
        const CryptomatteManifest manifest = cryptomatteManifest(layer);
        std::vector<std::string> names;
        for (const auto& [name, hash] : manifest.names) names.push_back(name);
        const char* source = manifest.source == CryptomatteManifest::Source::Header    ? "header"
                             : manifest.source == CryptomatteManifest::Source::Sidecar ? "sidecar"
                                                                                       : "none";
        const std::vector<std::string> shown(names.begin(), names.begin() + std::ptrdiff_t(std::min(names.size(), kShownNames)));
        o.out << fmt::format("  {} ({}, key {}, {}, {}): {} name(s){}{}{}\n", layer.name, layer.file, layer.key,
                             layer.hash.empty() ? "hash unnamed" : layer.hash,
                             manifest.source == CryptomatteManifest::Source::Header    ? "manifest in the header"
                             : manifest.source == CryptomatteManifest::Source::Sidecar ? "sidecar manifest"
                                                                                       : "no manifest",
                             names.size(), shown.empty() ? "" : ": ", fmt::join(shown, ", "),
                             names.size() > shown.size() ? fmt::format(" and {} more", names.size() - shown.size()) : "");
        for (const std::string& warning : manifest.warnings) o.out << "    " << warning << "\n";
        o.doc["cryptomatte"].push_back({{"name", layer.name}, {"file", layer.file}, {"key", layer.key},
                                        {"hash", layer.hash}, {"manifest", source}, {"names", names},
                                        {"warnings", manifest.warnings}});
    }
}

void printMapping(const InfoOutput& o, const std::vector<ExrImage>& files, const ChannelMapping& mapping) {
    o.out << "profile: " << mapping.profile << "\n";
    o.out << "profile scores:";
    nlohmann::ordered_json scores = nlohmann::ordered_json::object();
    for (const ProfileCandidate& c : mapping.candidates) {
        o.out << fmt::format(" {} {:g}", c.name, c.score);
        scores[c.name] = c.score;
    }
    o.out << "\n";
    // The notes say where each attribute comes from ("depth <- Z (generic)"): the mapping, once.
    for (const std::string& note : mapping.notes) o.out << "  " << note << "\n";
    nlohmann::ordered_json attributes = nlohmann::ordered_json::object();
    for (const auto& [attribute, refs] : mapping.attributes) {
        std::vector<std::string> names;
        for (const ChannelRef& ref : refs)
            names.push_back(
                files[std::size_t(ref.file)].parts[std::size_t(ref.part)].channels[std::size_t(ref.channel)].qualified);
        const std::string& file = files[std::size_t(refs.front().file)].path;
        attributes[attributeName(attribute)] = {{"channels", names}, {"file", file}};
    }
    o.doc["profile"] = mapping.profile;
    o.doc["profile_scores"] = scores;
    o.doc["profile_notes"] = mapping.notes;
    o.doc["attributes"] = attributes;
}

void printCamera(const InfoOutput& o, const Camera& camera, const CameraSolveReport& solve) {
    o.out << "camera: " << camera.source << (camera.isOrthographic() ? " (orthographic)" : " (perspective)")
          << fmt::format(", near {:.6g}, far {:.6g}\n", camera.nearPlane(), camera.farPlane());
    nlohmann::ordered_json json = {{"source", camera.source},
                                   {"orthographic", camera.isOrthographic()},
                                   {"near", camera.nearPlane()},
                                   {"far", camera.farPlane()}};
    if (solve.points > 0) {
        o.out << "camera solve: " << solve.summary() << "\n";
        o.out << "  near/far: " << solve.near_far_rule << "\n";
        for (const std::string& note : solve.notes) o.out << "  " << note << "\n";
        json["solve"] = {{"summary", solve.summary()}, {"near_far", solve.near_far_rule}, {"notes", solve.notes}};
    }
    printMatrix(o.out, "world_to_camera", camera.world_to_camera);
    printMatrix(o.out, "projection", camera.projection);
    json["world_to_camera"] = matrixJson(camera.world_to_camera);
    json["projection"] = matrixJson(camera.projection);
    o.doc["camera"] = json;
}

void printInfo(const InfoFlags& f) {
    nlohmann::ordered_json doc = {{"files", nlohmann::json::array()}};
    std::ostream dropped(nullptr);  // --json: the text goes nowhere
    const InfoOutput o{f.json ? dropped : std::cout, doc};

    const FrameFiles frame = readFrameFiles(f.inputs.front(), {f.inputs.begin() + 1, f.inputs.end()},
                                            parsePassFlags(f.passes));
    const std::vector<ExrImage>& files = frame.files;
    for (const ExrImage& image : files) printFile(o, image);
    printCryptomatte(o, files);
    ChannelMapping mapping = mapChannels(files, f.mapping, frame.roles);
    printMapping(o, files, mapping);

    std::optional<GBuffer> gbuffer;
    try {
        gbuffer = extractGBuffer(files, mapping);
        const FrameWindow window = frameWindow(files, mapping);
        o.out << fmt::format("g-buffer window: {} of display window {} (from {})\n", windowText(window.data),
                             windowText(window.display), window.owner);
        doc["gbuffer"] = {{"data_window", windowJson(window.data)}, {"display_window", windowJson(window.display)},
                          {"from", window.owner}};
    } catch (const Error& e) {
        o.out << "g-buffer: cannot extract (" << e.what() << ")\n";
        doc["gbuffer"] = {{"error", e.what()}};
    }
    std::optional<Camera> camera;
    try {
        CameraSolveReport solve;
        camera = gbuffer ? resolveCamera(files, *gbuffer, f.camera, &solve) : resolveCamera(files.front(), f.camera);
        printCamera(o, *camera, solve);
    } catch (const Error& e) {
        o.out << "camera: none (" << e.what() << ")\n";
        doc["camera"] = {{"error", e.what()}};
    }
    if (gbuffer && camera) {
        const DepthCheck check = settleDepthConvention(*gbuffer, mapping, *camera);
        o.out << "depth check: " << check.summary() << "\n";
        doc["depth_check"] = check.summary();
        if (gbuffer->has(Attribute::Normal)) {
            const std::string normal_check = settleNormalEncoding(*gbuffer, mapping, *camera).summary();
            o.out << "normal check: " << normal_check << "\n";
            doc["normal_check"] = normal_check;
        }
    }
    o.out << "depth convention: " << depthConventionName(mapping.depth_convention)
          << (mapping.reversed_z ? " (reversed-z)" : "") << "\n";
    doc["depth_convention"] = depthConventionName(mapping.depth_convention);
    doc["reversed_z"] = mapping.reversed_z;
    if (mapping.attributes.count(Attribute::Normal)) {
        o.out << "normals: " << normalSpaceName(mapping.normals.space) << " space, "
              << (mapping.normals.packed ? "packed" : "signed") << "\n";
        doc["normals"] = {{"space", normalSpaceName(mapping.normals.space)}, {"packed", mapping.normals.packed}};
    }
    o.out << "beauty:\n";
    const std::vector<std::string> beauty = findBeautyPasses(files, mapping, f.mapping).describe();
    for (const std::string& line : beauty) o.out << "  " << line << "\n";
    doc["beauty"] = beauty;
    if (f.json) std::cout << doc.dump(2) << "\n";
}

}  // namespace

Command addInfoCommand(CLI::App& app) {
    auto flags = std::make_shared<InfoFlags>();
    CLI::App* cmd = app.add_subcommand("info", "Show an EXR's channels, the matched profile, camera and depth convention");
    cmd->add_option("inputs", flags->inputs, "EXR file(s); several are pooled as in composite")->required();
    cmd->add_option("--camera", flags->camera, "Camera JSON sidecar");
    cmd->add_flag("--json", flags->json, "Print everything as one JSON document");
    addMappingOptions(*cmd, flags->mapping, flags->channels, flags->depth, /*writes=*/false);
    addPassOptions(*cmd, flags->passes);
    return [flags] {
        finishMappingOptions(flags->mapping, flags->channels, flags->depth);
        printInfo(*flags);
    };
}

}  // namespace decalcomp::cli
