#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "decalcomp/pipeline.hpp"

namespace decalcomp::cli {

namespace {

struct CompositeFlags {
    CompositeRequest request;
    std::vector<std::string> inputs;
    std::vector<std::string> passes;
    std::vector<std::string> channels;
    std::string depth;
    bool quiet = false;
};

}  // namespace

Command addCompositeCommand(CLI::App& app) {
    auto flags = std::make_shared<CompositeFlags>();
    CLI::App* cmd = app.add_subcommand("composite", "Composite a decal scene into a G-buffer EXR");
    CompositeRequest& r = flags->request;
    cmd->add_option("inputs", flags->inputs,
                    "G-buffer EXR(s): single- or multi-part, or several files whose channels are pooled")
        ->required();
    cmd->add_option("--decals", r.scene, "Decal scene JSON (docs/scene-format.md)")->required();
    cmd->add_option("--camera", r.camera_json,
                    "Camera JSON sidecar (default: an input header's worldToCamera/worldToNDC, else solved from "
                    "the position pass)");
    cmd->add_option("-o,--output", r.output,
                    "Output EXR (same layout as the input holding the albedo), or a folder when the composited "
                    "channels live in several files")
        ->required();
    cmd->add_option("--preview", r.preview, "Also write a PNG: input albedo | composited albedo");
    cmd->add_option("--device", r.device, "OpenCL device: index, gpu, cpu or part of its name (default: GPU, else CPU)");
    cmd->add_flag("--overwrite-input", r.overwrite_input, "Allow the output to replace the input file");
    cmd->add_flag("--unbinned", [&r](std::int64_t) { r.binned = false; }, "Test every decal at every pixel (debugging)");
    cmd->add_flag("-q,--quiet", flags->quiet, "Print nothing on success");
    addMappingOptions(*cmd, r.mapping, flags->channels, flags->depth);
    addPassOptions(*cmd, flags->passes);
    return [flags] {
        finishMappingOptions(flags->request.mapping, flags->channels, flags->depth);
        CompositeRequest& request = flags->request;
        request.input = flags->inputs.front();
        request.extra_inputs.assign(flags->inputs.begin() + 1, flags->inputs.end());
        request.pass_files = parsePassFlags(flags->passes);
        const CompositeReport report = compositeFile(request);
        // Warnings are not success chatter: they go to stderr even with --quiet.
        for (const std::string& warning : report.warnings) std::cerr << "decalcomp: warning: " << warning << "\n";
        if (flags->quiet) return;
        std::string written;
        for (const std::string& path : report.outputs) written += (written.empty() ? "" : ", ") + path;
        std::cout << fmt::format("{}: {} decals on {} ({} profile, camera from {}), kernels {:.2f} ms\n", written,
                                 report.stats.decals, report.device, report.mapping.profile, report.camera_source,
                                 report.stats.totalKernelMs());
        if (report.camera_solve)
            std::cout << "camera solve: " << report.camera_solve->summary() << fmt::format(
                ", near {:.6g}, far {:.6g}\n", report.camera_solve->near_plane, report.camera_solve->far_plane);
        if (report.depth_check.performed) std::cout << "depth check: " << report.depth_check.summary() << "\n";
        if (report.normal_check.performed) std::cout << "normal check: " << report.normal_check.summary() << "\n";
    };
}

}  // namespace decalcomp::cli
