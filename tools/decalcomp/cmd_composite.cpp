#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "decalcomp/frame.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp::cli {

namespace {

struct CompositeFlags {
    FrameSources sources;
    FrameTargets targets;
    FrameOptions options;
    std::string scene, device;
    SceneOptions scene_options;
    std::vector<std::string> passes;
    std::vector<std::string> channels;
    std::string depth;
    bool quiet = false, stats = false;
};

// --stats: what the device and the EXR writer did, one fact a line.
void printStats(const FrameReport& report) {
    const CompositeStats& s = report.stats;
    std::cout << fmt::format("stats: decals {}, tiles {}, bin entries {}\n", s.decals, s.tiles, s.bin_entries)
              << fmt::format("stats: kernels {:.2f} ms (tile bounds {:.2f}, binning {:.2f}, shading {:.2f}, "
                             "occlusion {:.2f})\n",
                             s.totalKernelMs(), s.tile_bounds_ms, s.binning_ms, s.shading_ms, s.occlusion_ms)
              << fmt::format("stats: changed samples {}\n", report.changed_samples)
              << fmt::format("stats: chunks copied {}, chunks re-encoded {}, pixels re-encoded {}\n",
                             report.chunks_copied, report.chunks_reencoded, report.pixels_reencoded);
}

}  // namespace

Command addCompositeCommand(CLI::App& app) {
    auto flags = std::make_shared<CompositeFlags>();
    CLI::App* cmd = app.add_subcommand("composite", "Composite a decal scene into a G-buffer EXR");
    cmd->add_option("inputs", flags->sources.inputs,
                    "G-buffer EXR(s): single- or multi-part, or several files whose channels are pooled")
        ->required();
    cmd->add_option("--decals", flags->scene, "Decal scene JSON (docs/scene-format.md)")->required();
    addOcioOption(*cmd, flags->scene_options.ocio_config);
    cmd->add_option("--camera", flags->sources.camera_json,
                    "Camera JSON sidecar (default: an input header's worldToCamera/worldToNDC, else solved from "
                    "the position pass)");
    cmd->add_option("-o,--output", flags->targets.output,
                    "Output EXR (same layout as the input holding the albedo), or a folder when the composited "
                    "channels live in several files")
        ->required();
    cmd->add_option("--preview", flags->targets.preview, "Also write a PNG: input albedo | composited albedo");
    cmd->add_option("--device", flags->device, "OpenCL device: index, gpu, cpu or part of its name (default: GPU, else CPU)");
    cmd->add_flag("--overwrite-input", flags->targets.overwrite_input, "Allow the output to replace the input file");
    cmd->add_flag("--force", flags->targets.force, "Composite even when the input's header says this scene is already in it");
    CompositeOptions& compositing = flags->options.compositing;
    cmd->add_flag("--unbinned", [&compositing](std::int64_t) { compositing.binned = false; }, "Test every decal at every pixel (debugging)");
    cmd->add_flag("-q,--quiet", flags->quiet, "Print nothing on success");
    cmd->add_flag("--stats", flags->stats,
                  "Print the device's and the writer's figures: kernels, changed samples, chunks copied and re-encoded "
                  "(even with --quiet)");
    addMappingOptions(*cmd, flags->options.mapping, flags->channels, flags->depth);
    addBeautyOptions(*cmd, flags->options.beauty);
    addPixelFilterOption(*cmd, flags->options.pixel_filter, flags->options.pixel_filter_fast);
    addUvOriginOption(*cmd, flags->options.uv_v_down);
    addPassOptions(*cmd, flags->passes);
    return [flags] {
        finishMappingOptions(flags->options.mapping, flags->channels, flags->depth);
        flags->sources.pass_files = parsePassFlags(flags->passes);
        // Inputs, scene, outputs and camera are checked before the device is opened.
        Frame frame(flags->sources, flags->targets, flags->options);
        const DecalScene scene = loadScene(flags->scene, flags->scene_options);
        frame.prepare(scene);
        const std::chrono::milliseconds notice_after = slowBuildNoticeAfter();
        ComputeDevice device(flags->device);
        if (!flags->quiet)
            device.setSlowBuildNotice(notice_after,
                                      [](const std::string& m) { std::cerr << "decalcomp: note: " + m + "\n"; });
        Compositor compositor(device);
        compositor.setScene(scene);
        frame.composite(compositor);
        frame.writeBack();
        const FrameReport& report = frame.report();
        // Warnings are not success chatter: they go to stderr even with --quiet.
        for (const std::string& warning : report.warnings) std::cerr << "decalcomp: warning: " << warning << "\n";
        if (flags->stats) printStats(report);
        if (flags->quiet) return;
        std::string written;
        for (const std::string& path : report.outputs) written += (written.empty() ? "" : ", ") + path;
        std::cout << fmt::format("{}: {} decals on {} ({} profile, camera from {}), kernels {:.2f} ms\n", written,
                                 report.stats.decals, device.info().name, report.mapping.profile, report.camera_source,
                                 report.stats.totalKernelMs())
                  << "chunks: "
                  << chunkSummary({report.chunks_copied, report.chunks_reencoded, report.pixels_reencoded}) << "\n";
        if (report.camera_solve)
            std::cout << "camera solve: " << report.camera_solve->summary() << fmt::format(
                ", near {:.6g}, far {:.6g}\n", report.camera_solve->near_plane, report.camera_solve->far_plane);
        if (report.beauty.rebuilt) {
            std::cout << "beauty: " << report.beauty.summary << "\n";
            if (report.beauty.fit)
                std::cout << fmt::format("relight: direct light fit over {} pixels, rms residual {:.4g}\n",
                                         report.beauty.fit->pixels, report.beauty.fit->rms);
        }
        if (!report.pixel_filter.empty()) std::cout << "pixel filter: " << report.pixel_filter << "\n";
        if (report.depth_check.performed) std::cout << "depth check: " << report.depth_check.summary() << "\n";
        if (report.normal_check.performed) std::cout << "normal check: " << report.normal_check.summary() << "\n";
    };
}

}  // namespace decalcomp::cli
