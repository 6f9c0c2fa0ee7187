// The files of a batch's frames: inputs, outputs, the check that the range is complete, output
// folders and the temporaries a killed run left.
#include "batch/batch_files.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <map>
#include <set>

#include "decalcomp/error.hpp"
#include "decalcomp/gbuffer.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/temporary_files.hpp"

namespace decalcomp::batch {

namespace fs = std::filesystem;

namespace {

// An input of the range that is not there.
struct MissingInput {
    int frame = 0;
    std::string path, field, problem;  // "in/f.0005.exr", "frame 5 --pass depth", "no such file"
};

// Why `path` cannot be read as a file; "" when it can be.
std::string fileProblem(const std::string& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) return "no such file";
    if (fs::is_directory(status)) return "a folder, not a file";
    return "";
}

// The frame's inputs that are missing, in the order the frame reads them.
std::vector<MissingInput> missingInputs(const BatchRequest& request, const BatchPlan& plan, const FrameCameras& cameras,
                                        int frame) {
    std::vector<std::pair<std::string, std::string>> files;  // path, what names it
    const FrameSources sources = frameSources(request, plan, frame);
    for (const std::string& input : sources.inputs) files.emplace_back(input, "input");
    for (const auto& [attribute, path] : sources.pass_files)
        files.emplace_back(path, fmt::format("--pass {}", attributeName(attribute)));
    if (const std::string sidecar = cameras.sidecarPath(frame); !sidecar.empty())
        files.emplace_back(sidecar, "--camera");

    std::vector<MissingInput> missing;
    std::set<std::string> seen;  // a file named twice is reported once
    for (const auto& [path, what] : files)
        if (seen.insert(path).second)
            if (std::string problem = fileProblem(path); !problem.empty())
                missing.push_back({frame, path, fmt::format("frame {} {}", frame, what), std::move(problem)});
    if (!cameras.hasFrame(frame))
        missing.push_back({frame, cameras.perFrameFile(), "frames", fmt::format("no camera for frame {}", frame)});
    return missing;
}

// "frames 5, 7, 9" (the first ten, then how many in all).
std::string frameList(const std::vector<int>& frames) {
    constexpr std::size_t kShown = 10;
    const std::vector<int> shown(frames.begin(), frames.begin() + std::ptrdiff_t(std::min(frames.size(), kShown)));
    std::string text = fmt::format("frame{} {}", frames.size() > 1 ? "s" : "", fmt::join(shown, ", "));
    if (frames.size() > kShown) text += fmt::format(", ... ({} frames)", frames.size());
    return text;
}

}  // namespace

std::string pathAt(const std::string& pattern_or_path, int frame) {
    return FramePattern::hasToken(pattern_or_path) ? FramePattern(pattern_or_path).path(frame) : pattern_or_path;
}

FrameSources frameSources(const BatchRequest& request, const BatchPlan& plan, int frame) {
    FrameSources sources;
    sources.inputs.push_back(plan.input.path(frame));
    for (const std::string& extra : request.extra_inputs) sources.inputs.push_back(pathAt(extra, frame));
    for (const auto& [attribute, pattern] : request.pass_files) sources.pass_files[attribute] = pathAt(pattern, frame);
    return sources;
}

std::vector<fs::path> candidateOutputs(const BatchRequest& request, const BatchPlan& plan, int frame) {
    if (!plan.outputIsFolder()) return {fs::path(plan.outputAt(frame))};
    const fs::path folder(plan.outputAt(frame));
    FrameSources sources = frameSources(request, plan, frame);
    for (const auto& [attribute, path] : sources.pass_files) sources.inputs.push_back(path);
    std::vector<fs::path> paths;
    for (const std::string& input : sources.inputs) paths.push_back(folder / fs::path(input).filename());
    return paths;
}

bool frameDone(const BatchRequest& request, const BatchPlan& plan, int frame) {
    std::error_code ec;
    for (const fs::path& path : candidateOutputs(request, plan, frame))
        if (fs::is_regular_file(path, ec)) return true;
    return false;
}

void requireRangeInputs(const BatchRequest& request, const BatchPlan& plan, const FrameCameras& cameras) {
    std::vector<MissingInput> missing;
    std::vector<int> frames;  // with something missing
    for (int frame : plan.frames) {
        if (request.resume && frameDone(request, plan, frame)) continue;  // will be skipped, not read
        std::vector<MissingInput> more = missingInputs(request, plan, cameras, frame);
        if (more.empty()) continue;
        frames.push_back(frame);
        missing.insert(missing.end(), more.begin(), more.end());
    }
    if (missing.empty()) return;
    const MissingInput& first = missing.front();
    const std::string others =
        missing.size() == 1 ? std::string()
                            : fmt::format(" ({} inputs missing in all, in {})", missing.size(), frameList(frames));
    throw inputError(
        fmt::format("{}: {}: {}{}; nothing was written: render or restore {}, narrow --frames, or pass "
                    "--keep-going to process the other frames",
                    first.path, first.field, first.problem, others, missing.size() == 1 ? "it" : "them"));
}

void checkContactSheet(const BatchRequest& request, const BatchPlan& plan, const DecalScene& scene,
                       const std::string& sheet) {
    if (!hasExtension(sheet, ".png"))
        throw Error(ErrorKind::Usage, fmt::format("--contact-sheet {}: the sheet is written as PNG; give it a .png name", sheet));
    std::vector<std::pair<std::string, std::string>> files = {  // path, what it is
        {request.scene, "the scene"}, {request.ocio_config, "the OpenColorIO config"}, {request.cameras, "the cameras file"}};
    for (const std::string& profile : request.mapping.profile_files) files.emplace_back(profile, "a profile");
    for (const Texture2D& texture : scene.textures) files.emplace_back(texture.source, "a texture of the scene");
    for (const RestMesh& mesh : scene.meshes) files.emplace_back(mesh.source, "a rest mesh of the scene");
    for (int frame : plan.frames) {
        const FrameSources sources = frameSources(request, plan, frame);
        for (const std::string& input : sources.inputs) files.emplace_back(input, fmt::format("frame {}'s input", frame));
        for (const auto& [attribute, path] : sources.pass_files)
            files.emplace_back(path, fmt::format("frame {}'s --pass {}", frame, attributeName(attribute)));
        for (const fs::path& out : candidateOutputs(request, plan, frame))
            files.emplace_back(out.string(), fmt::format("frame {}'s output", frame));
        if (!request.preview.empty()) files.emplace_back(pathAt(request.preview, frame), fmt::format("frame {}'s preview", frame));
        if (!request.camera.empty()) files.emplace_back(pathAt(request.camera, frame), fmt::format("frame {}'s camera", frame));
    }
    for (const auto& [path, what] : files)
        if (!path.empty() && sameFile(sheet, path))
            throw Error(ErrorKind::Usage,
                        fmt::format("--contact-sheet {}: the contact sheet would replace {} ({})", sheet, what, path));
}

void createOutputFolders(const BatchRequest& request, const BatchPlan& plan) {
    std::set<fs::path> folders;
    if (!request.contact_sheet.empty()) folders.insert(fs::path(request.contact_sheet).parent_path());
    for (int frame : plan.frames) {
        for (const fs::path& out : candidateOutputs(request, plan, frame)) folders.insert(out.parent_path());
        if (!request.preview.empty()) folders.insert(fs::path(pathAt(request.preview, frame)).parent_path());
    }
    for (const fs::path& folder : folders) {
        if (folder.empty()) continue;
        std::error_code ec;
        fs::create_directories(folder, ec);
        if (ec)
            throw outputError(fmt::format("{}: cannot create the output folder: {}", folder.string(), ec.message()));
    }
}

void removeStaleTemporaries(const BatchRequest& request, const BatchPlan& plan) {
    std::map<fs::path, std::set<std::string>> names;  // folder -> names of outputs and previews
    for (int frame : plan.frames) {
        for (const fs::path& out : candidateOutputs(request, plan, frame))
            names[out.parent_path()].insert(out.filename().string());
        if (!request.preview.empty()) {
            const fs::path preview(pathAt(request.preview, frame));
            names[preview.parent_path()].insert(preview.filename().string());
        }
    }
    for (const auto& [folder, files] : names) {
        std::error_code ec;
        const fs::path dir = folder.empty() ? fs::path(".") : folder;
        for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string name = it->path().filename().string();
            const auto tmp = name.rfind(".tmp-");
            if (name.size() < 2 || name[0] != '.' || tmp == std::string::npos || tmp < 2) continue;
            if (files.count(name.substr(1, tmp - 1))) {
                std::error_code ignored;
                fs::remove(it->path(), ignored);
            }
        }
    }
}

int framesInFlight(const BatchRequest& request, int workers) {
    const int outputs = 1 + int(request.extra_inputs.size() + request.pass_files.size());  // at most one per file
    const int per_frame = outputs + (request.preview.empty() ? 0 : 1);
    const int wanted = 2 * std::max(1, request.queue_depth) + workers + 1;
    return std::max(1, std::min(wanted, (kMaxLiveTemporaries - 1) / per_frame));
}

}  // namespace decalcomp::batch
