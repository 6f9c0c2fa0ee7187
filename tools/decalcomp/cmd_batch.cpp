#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "decalcomp/batch.hpp"
#include "decalcomp/batch_progress.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp::cli {

namespace {

struct BatchFlags {
    BatchRequest request;
    std::vector<std::string> inputs, passes, channels;
    std::string depth;
    std::string shard, shard_mode = "interleaved", progress = "auto";
    bool quiet = false, list_frames = false, no_slurm = false, timing = false, stats = false;
};

ProgressStyle progressStyle(const BatchFlags& f) {
    if (f.quiet || f.progress == "none") return ProgressStyle::Quiet;
    if (f.progress == "bar") return ProgressStyle::Bar;
    if (f.progress == "lines") return ProgressStyle::Lines;
    return ::isatty(::fileno(stderr)) ? ProgressStyle::Bar : ProgressStyle::Lines;
}

void run(BatchFlags& f) {
    BatchRequest& r = f.request;
    finishMappingOptions(r.mapping, f.channels, f.depth);
    r.input = f.inputs.front();
    r.extra_inputs.assign(f.inputs.begin() + 1, f.inputs.end());
    r.pass_files = parsePassFlags(f.passes);
    if (!f.shard.empty()) r.shard = parseShard(f.shard);
    r.shard_from_environment = !f.no_slurm;
    r.shard_mode = f.shard_mode == "contiguous" ? ShardMode::Contiguous : ShardMode::Interleaved;
    if (f.list_frames) {
        for (int frame : planBatch(r).frames) std::cout << frame << "\n";
        return;
    }
    if (r.scene.empty() && !r.io_only) throw Error(ErrorKind::Usage, "--decals is required (or --io-only)");
    ProgressPrinter printer(std::cerr, progressStyle(f));
    const BatchReport report = runBatch(r, &printer);
    for (const std::string& warning : report.warnings) std::cerr << "decalcomp: warning: " << warning << "\n";
    if (!f.quiet) {
        for (const std::string& note : report.beauty) std::cout << "beauty: " << note << "\n";
        for (const std::string& note : report.pixel_filter) std::cout << "pixel filter: " << note << "\n";
        if (!report.contact_sheet.empty()) std::cout << "contact sheet: " << report.contact_sheet << "\n";
    }
    if (f.timing) {
        const BatchTimings& t = report.timings;
        const double n = std::max(1, report.progress.written + report.progress.failed);
        std::cerr << fmt::format(
            "timing, ms per frame (thread time): read {:.1f}, prepare {:.1f}, composite {:.1f} (kernels {:.2f}), "
            "encode {:.1f}, write {:.1f}; reader blocked {:.1f}, writer idle {:.1f}\n",
            1e3 * t.read_s / n, 1e3 * t.prepare_s / n, 1e3 * t.composite_s / n, t.kernels_ms / n, 1e3 * t.encode_s / n,
            1e3 * t.write_s / n, 1e3 * t.read_wait_s / n, 1e3 * t.write_idle_s / n);
        std::cerr << fmt::format(
            "timing, ms per frame (CPU time): prepare {:.1f}, composite {:.1f} (the workers' threads); decode {:.1f}, "
            "encode {:.1f} (every thread)\n",
            1e3 * t.prepare_cpu_s / n, 1e3 * t.composite_cpu_s / n, 1e3 * t.decode_cpu_s / n, 1e3 * t.encode_cpu_s / n);
    }
    if (f.stats)
        std::cout << fmt::format("stats: frames written {}, chunks copied {}, chunks re-encoded {}, pixels re-encoded {}\n",
                                 report.progress.written, report.chunks.copied, report.chunks.reencoded,
                                 report.chunks.pixels_reencoded);
    if (report.failures.empty()) return;
    // --keep-going: every failed frame, then a non-zero exit with the first failure's code.
    std::string frames;
    for (const FrameResult& failed : report.failures) {
        std::cerr << fmt::format("decalcomp: error: {} (frame {})\n", failed.message, failed.frame);
        frames += (frames.empty() ? "" : ", ") + std::to_string(failed.frame);
    }
    const std::string summary = fmt::format("{} of {} frames failed: {}", report.failures.size(),
                                            report.progress.total, frames);
    const FrameResult& first = report.failures.front();
    if (first.kind) throw Error(*first.kind, summary);
    throw std::runtime_error(summary);  // a frame failed on a bug: main reports an internal error
}

}  // namespace

Command addBatchCommand(CLI::App& app) {
    auto flags = std::make_shared<BatchFlags>();
    CLI::App* cmd = app.add_subcommand("batch", "Composite a decal scene into every frame of a sequence");
    BatchRequest& r = flags->request;
    cmd->add_option("inputs", flags->inputs,
                    "Input frame pattern(s): frame.####.exr or frame.%04d.exr; frames are found from the first, "
                    "further files' channels are pooled with it")
        ->required();
    cmd->add_option("-o,--output", r.output,
                    "Output frame pattern, or a folder where each changed file keeps its name (folders are created)")
        ->required();
    cmd->add_option("--preview", r.preview, "Also write a PNG per frame (a pattern: preview.####.png)");
    cmd->add_option("--contact-sheet", r.contact_sheet,
                    "Also write one PNG with a thumbnail of every composited frame, in frame order (a sharded run "
                    "writes NAME.shard-K-of-N.png per shard)");
    cmd->add_option("--decals", r.scene, "Decal scene JSON; decals may have lifetimes and keyframes");
    addOcioOption(*cmd, r.ocio_config);
    cmd->add_option("--frames", r.frames, "Frames: 1-240, 1-240x2, 1,5,10-20 (default: every input that exists)");
    cmd->add_option("--camera", r.camera,
                    "Camera sidecar for every frame, or a sidecar pattern (cam.####.json); default: each frame's "
                    "header, else solved from its position pass");
    cmd->add_option("--cameras", r.cameras, "One JSON file with a camera per frame (docs/cli.md)");
    cmd->add_option("--device", r.device,
                    "OpenCL device(s): index, gpu, cpu or part of its name; several separated by ',', or all "
                    "(every GPU); frames are spread over them");
    cmd->add_flag("--resume", r.resume, "Skip frames whose output exists (outputs are written atomically)");
    cmd->add_flag("--keep-going", r.keep_going,
                  "Go on past failed frames; list them and exit non-zero at the end (without it every input "
                  "of the range must exist, and the first failing frame stops the batch)");
    cmd->add_option("--shard", flags->shard,
                    "Process the I-th of N slices of the frames, I from 1 (default in a Slurm job array: from "
                    "SLURM_ARRAY_TASK_ID/COUNT/MIN)");
    cmd->add_option("--shard-mode", flags->shard_mode, "interleaved (1, N+1, ...) or contiguous (chunks)")
        ->check(CLI::IsMember({"interleaved", "contiguous"}))
        ->default_str("interleaved");
    cmd->add_flag("--no-slurm-shard", flags->no_slurm, "Ignore SLURM_ARRAY_* (process every frame in each task)");
    cmd->add_option("--threads", r.exr_threads, "OpenEXR decode/encode threads (default: all hardware threads)")
        ->check(CLI::Range(0, 1024));
    cmd->add_option("--queue", r.queue_depth, "Frames waiting between read, composite and write (memory bound)")
        ->check(CLI::Range(1, 64))
        ->default_str("2");
    cmd->add_option("--workers", r.composite_workers,
                    "Compositing threads per device (their host-side work overlaps; default: a quarter of the "
                    "hardware threads shared among the devices, 2 to 8)")
        ->check(CLI::Range(1, 64))
        ->default_str("auto");
    cmd->add_flag("--io-only", r.io_only, "Read and write every frame without compositing (measures the I/O)");
    cmd->add_flag("--list-frames", flags->list_frames, "Print the frames this run (shard) would process, and exit");
    cmd->add_flag("--overwrite-input", r.overwrite_input, "Allow outputs to replace their inputs");
    cmd->add_flag("--force", r.force, "Composite frames whose header says this scene is already in them");
    cmd->add_flag("--unbinned", [&r](std::int64_t) { r.binned = false; }, "Test every decal at every pixel (debugging)");
    cmd->add_option("--progress", flags->progress, "auto (bar on a terminal, else lines), bar, lines, none")
        ->check(CLI::IsMember({"auto", "bar", "lines", "none"}))
        ->default_str("auto");
    cmd->add_flag("-q,--quiet", flags->quiet, "No progress; only errors");
    cmd->add_flag("--timing", flags->timing, "Print where the time went, per stage (ms per frame)");
    cmd->add_flag("--stats", flags->stats,
                  "Print the chunks the writes copied and re-encoded, summed over the frames (even with --quiet)");
    addMappingOptions(*cmd, r.mapping, flags->channels, flags->depth);
    addBeautyOptions(*cmd, r.beauty);
    addPixelFilterOption(*cmd, r.pixel_filter, r.pixel_filter_fast);
    addUvOriginOption(*cmd, r.uv_v_down);
    addPassOptions(*cmd, flags->passes);
    return [flags] { run(*flags); };
}

}  // namespace decalcomp::cli
