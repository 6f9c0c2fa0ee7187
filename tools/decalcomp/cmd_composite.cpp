#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "decalcomp/pipeline.hpp"

namespace decalcomp::cli {

namespace {

struct CompositeFlags {
    CompositeRequest request;
    std::vector<std::string> channels;
    std::string depth;
    bool quiet = false;
};

}  // namespace

Command addCompositeCommand(CLI::App& app) {
    auto flags = std::make_shared<CompositeFlags>();
    CLI::App* cmd = app.add_subcommand("composite", "Composite a decal scene into a G-buffer EXR");
    CompositeRequest& r = flags->request;
    cmd->add_option("input", r.input, "G-buffer EXR (single- or multi-part)")->required();
    cmd->add_option("--decals", r.scene, "Decal scene JSON (docs/scene-format.md)")->required();
    cmd->add_option("--camera", r.camera_json, "Camera JSON sidecar (default: the EXR header's worldToCamera/worldToNDC)")
        ;
    cmd->add_option("-o,--output", r.output, "Output EXR (same layout as the input)")->required();
    cmd->add_option("--preview", r.preview, "Also write a PNG: input albedo | composited albedo");
    cmd->add_option("--device", r.device, "OpenCL device: index, gpu, cpu or part of its name (default: GPU, else CPU)");
    cmd->add_flag("--overwrite-input", r.overwrite_input, "Allow the output to replace the input file");
    cmd->add_flag("--unbinned", [&r](std::int64_t) { r.binned = false; }, "Test every decal at every pixel (debugging)");
    cmd->add_flag("-q,--quiet", flags->quiet, "Print nothing on success");
    addMappingOptions(*cmd, r.mapping, flags->channels, flags->depth);
    return [flags] {
        finishMappingOptions(flags->request.mapping, flags->channels, flags->depth);
        const CompositeReport report = compositeFile(flags->request);
        if (flags->quiet) return;
        std::cout << fmt::format("{}: {} decals on {} ({} profile, camera from {}), kernels {:.2f} ms\n",
                                 flags->request.output, report.stats.decals, report.device, report.mapping.profile,
                                 report.camera_source, report.stats.totalKernelMs());
    };
}

}  // namespace decalcomp::cli
