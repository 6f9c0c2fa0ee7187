#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <set>

#include "decalcomp/camera_solve.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/depth_check.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/header_camera.hpp"
#include "decalcomp/masks.hpp"
#include "decalcomp/normal_check.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp {

namespace fs = std::filesystem;

namespace {

// The same file named twice (a.exr, ./a.exr) is read once.
std::string fileKey(const std::string& path) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(path, ec);
    return ec ? path : canonical.string();
}

bool isFolder(const std::string& path) {
    std::error_code ec;
    return (!path.empty() && path.back() == '/') || fs::is_directory(path, ec);
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
                          const std::map<Attribute, std::string>& pass_files) {
    FrameFiles frame;
    std::map<std::string, int> seen;
    auto add = [&](const std::string& path) {
        const std::string key = fileKey(path);
        if (auto it = seen.find(key); it != seen.end()) return it->second;
        frame.files.push_back(readExr(path));
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

DepthCheck settleDepthConvention(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera) {
    DepthCheck check = checkDepthConvention(gbuffer, camera);
    mapping.notes.push_back("depth check: " + check.summary());
    if (check.verdict && *check.verdict != gbuffer.depth_convention) {
        if (mapping.depth_convention_explicit) {
            mapping.notes.push_back(fmt::format("depth convention stays {} (explicit --depth) although the position "
                                                "pass suggests {}",
                                                depthConventionName(gbuffer.depth_convention),
                                                depthConventionName(*check.verdict)));
        } else {
            gbuffer.depth_convention = *check.verdict;
            mapping.depth_convention = *check.verdict;
            mapping.notes.push_back(fmt::format("depth convention: {} (checked against the position pass)",
                                                depthConventionName(*check.verdict)));
        }
    }
    return check;
}

NormalCheck settleNormalEncoding(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera) {
    NormalConstraints fixed;
    if (mapping.normal_space_explicit) fixed.space = gbuffer.normal_encoding.space;
    if (mapping.normal_encoding_explicit) fixed.packed = gbuffer.normal_encoding.packed;
    NormalCheck check = checkNormalEncoding(gbuffer, camera, fixed);
    if (!gbuffer.has(Attribute::Normal)) return check;
    mapping.notes.push_back("normal check: " + check.summary());
    const NormalEncoding& current = gbuffer.normal_encoding;
    if (!check.verdict || (check.verdict->space == current.space && check.verdict->packed == current.packed)) return check;
    gbuffer.normal_encoding = *check.verdict;
    mapping.normal_space = normalSpaceName(check.verdict->space);
    mapping.normal_encoding = check.verdict->packed ? "unsigned" : "signed";
    mapping.notes.push_back(fmt::format("normals: {} space, {} (checked against the depth pass)", mapping.normal_space,
                                        check.verdict->packed ? "packed" : "signed"));
    return check;
}

std::map<int, std::string> outputPaths(const std::vector<ExrImage>& files, const ChannelMapping& mapping,
                                       const std::vector<Attribute>& attributes, const std::string& output) {
    std::set<int> changed;
    for (Attribute attribute : attributes)
        if (auto it = mapping.attributes.find(attribute); it != mapping.attributes.end())
            for (const ChannelRef& ref : it->second) changed.insert(ref.file);
    std::map<int, std::string> paths;
    if (changed.empty()) return paths;
    const bool folder = isFolder(output);
    if (changed.size() > 1 && !folder) {
        std::vector<std::string> names;
        for (int f : changed) names.push_back(files[std::size_t(f)].path);
        throw Error(ErrorKind::Usage,
                    fmt::format("{}: the composited channels live in {} files ({}): give -o an output folder "
                                "(an existing one, or a path ending in '/')",
                                output, changed.size(), fmt::join(names, ", ")));
    }
    std::map<std::string, int> names;
    for (int f : changed) {
        const std::string& input = files[std::size_t(f)].path;
        if (!folder) {
            paths[f] = output;
            continue;
        }
        const std::string name = fs::path(input).filename().string();
        if (auto it = names.find(name); it != names.end())
            throw Error(ErrorKind::Usage, fmt::format("{}: {} and {} would both be written as {}", output,
                                                      files[std::size_t(it->second)].path, input, name));
        names[name] = f;
        paths[f] = (fs::path(output) / name).string();
    }
    return paths;
}

void checkNotOverwritingInput(const std::string& input, const std::string& output, bool allowed) {
    std::error_code ec;
    const bool same = fs::exists(output, ec) && fs::equivalent(input, output, ec);
    if (same && !allowed)
        throw Error(ErrorKind::Usage, fmt::format("{}: output is the input file; pass --overwrite-input to replace it", output));
}

CompositeReport compositeFile(const CompositeRequest& request) {
    CompositeReport report;
    FrameFiles frame = readFrameFiles(request.input, request.extra_inputs, request.pass_files);
    std::vector<ExrImage>& files = frame.files;
    report.mapping = mapChannels(files, request.mapping, frame.roles);
    if (!report.mapping.attributes.count(Attribute::Albedo))
        throw inputError(fmt::format("{}: no albedo channels found (profile {}); map them with --channel albedo=R,G,B",
                                     request.input, report.mapping.profile));
    addAttributeChannels(files, report.mapping, request.mapping);
    // What changes, and where each changed file goes, decided (and checked) before any work.
    const DecalScene scene = loadScene(request.scene);
    const std::vector<Attribute> attributes = compositedAttributes(scene);
    report.warnings = missingAttributeWarnings(attributes, report.mapping, request.input);
    const std::map<int, std::string> outputs = outputPaths(files, report.mapping, attributes, request.output);
    for (const auto& [file, path] : outputs)
        for (const ExrImage& input : files) checkNotOverwritingInput(input.path, path, request.overwrite_input);

    GBuffer before = extractGBuffer(files, report.mapping);
    CameraSolveReport solve;
    const Camera camera = resolveCamera(files, before, request.camera_json, &solve);
    if (solve.points > 0) report.camera_solve = solve;
    report.camera_source = camera.source;
    report.depth_check = settleDepthConvention(before, report.mapping, camera);
    report.normal_check = settleNormalEncoding(before, report.mapping, camera);
    evaluateMasks(files, report.mapping, scene, before, &report.warnings);  // decal masks for this frame

    ComputeDevice device(request.device);
    report.device = device.info().name;
    Compositor compositor(device);
    compositor.setScene(scene);
    GBuffer after = before;
    report.stats = compositor.composite(after, camera, CompositeOptions{request.binned});
    for (Attribute attribute : attributes)
        if (after.has(attribute)) storeAttribute(files, report.mapping, attribute, after.planes.at(attribute));

    // Everything goes to temporary names first, so a failed write leaves none of the outputs behind.
    std::string preview_tmp;
    std::vector<std::pair<std::string, std::string>> written;  // temporary, final
    auto discardAll = [&] {
        for (const auto& [temporary, final_path] : written) discardExrTemporary(temporary);
        if (!preview_tmp.empty()) fs::remove(preview_tmp);
    };
    try {
        if (!request.preview.empty()) {
            preview_tmp = request.preview + ".partial.png";
            writePreview(before, after, camera, preview_tmp);
        }
        for (const auto& [file, path] : outputs) {
            const fs::path parent = fs::path(path).parent_path();
            std::error_code ec;
            if (!parent.empty() && isFolder(request.output)) fs::create_directories(parent, ec);
            written.emplace_back(writeExrTemporary(files[std::size_t(file)], path), path);
        }
        for (const auto& [temporary, final_path] : written) commitExrTemporary(temporary, final_path);
    } catch (...) {
        discardAll();
        throw;
    }
    for (const auto& [file, path] : outputs) report.outputs.push_back(path);
    if (!preview_tmp.empty()) {
        std::error_code ec;
        fs::rename(preview_tmp, request.preview, ec);
        if (ec) {
            fs::remove(preview_tmp);
            throw outputError(fmt::format("{}: cannot write preview: {}", request.preview, ec.message()));
        }
    }
    return report;
}

}  // namespace decalcomp
