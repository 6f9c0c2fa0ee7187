// A frame's files and camera, and what it lacks.
#include <fmt/format.h>

#include <filesystem>

#include "decalcomp/error.hpp"
#include "decalcomp/header_camera.hpp"
#include "decalcomp/pipeline.hpp"

namespace decalcomp {

namespace fs = std::filesystem;

namespace {

// The same file named twice (a.exr, ./a.exr) is read once.
std::string fileKey(const std::string& path) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(path, ec);
    return ec ? path : canonical.string();
}

}  // namespace

std::vector<std::string> missingAttributeWarnings(const std::vector<Attribute>& attributes, const ChannelMapping& mapping,
                                                  const std::string& input) {
    std::vector<std::string> warnings;
    for (Attribute attribute : attributes) {
        if (mapping.attributes.count(attribute)) continue;
        const std::string name = attributeName(attribute);
        // --add-channels makes material channels; a normal pass has to come from the renderer
        const std::string remedy = attribute == Attribute::Normal
                                       ? "map a normal pass with --channel normal=X,Y,Z"
                                       : fmt::format("map them with --channel {}=..., or add them with --add-channels {}",
                                                     name, name);
        warnings.push_back(fmt::format("{}: decals change {} but the input has no {} channels (profile {}); left out ({})",
                                       input, name, name, mapping.profile, remedy));
    }
    return warnings;
}

FrameFiles readFrameFiles(const std::string& input, const std::vector<std::string>& extra_inputs,
                          const std::map<Attribute, std::string>& pass_files, const ExrReadRegion& region) {
    FrameFiles frame;
    std::map<std::string, int> seen;
    auto add = [&](const std::string& path) {
        const std::string key = fileKey(path);
        if (auto it = seen.find(key); it != seen.end()) return it->second;
        frame.files.push_back(readExr(path, region));
        // A frame changes samples only through storeAttribute, which marks the chunks it changes.
        frame.files.back().copy_unchanged_chunks = true;
        seen[key] = int(frame.files.size()) - 1;
        return int(frame.files.size()) - 1;
    };
    add(input);
    for (const std::string& path : extra_inputs) add(path);
    frame.roles.positional = int(frame.files.size());
    for (const auto& [attribute, path] : pass_files) frame.roles.pass_files[attribute] = add(path);
    return frame;
}

Camera resolveCamera(const ExrImage& image, const std::string& camera_json) {
    if (!camera_json.empty()) return loadCameraJson(camera_json);
    for (const ExrPart& part : image.parts)
        if (auto camera = cameraFromExrHeader(part.header, image.path)) return *camera;
    throw inputError(fmt::format("{}: no camera: the header has no worldToCamera/worldToNDC; pass --camera camera.json",
                                 image.path));
}

Camera resolveCamera(const std::vector<ExrImage>& files, const GBuffer& gbuffer, const std::string& camera_json,
                     CameraSolveReport* solve) {
    if (!camera_json.empty()) return loadCameraJson(camera_json);
    if (files.empty()) throw inputError("no input files");
    for (const ExrImage& image : files)
        for (const ExrPart& part : image.parts)
            if (auto camera = cameraFromExrHeader(part.header, image.path)) return *camera;
    const std::string& label = files.front().path;
    if (!gbuffer.has(Attribute::Position))
        throw inputError(fmt::format("{}: no camera: no header has worldToCamera/worldToNDC and there is no position "
                                     "pass to solve one from; pass --camera camera.json",
                                     label));
    return solveCamera(gbuffer, label, solve);
}

}  // namespace decalcomp
