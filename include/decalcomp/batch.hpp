#pragma once
// Batch post-processing of rendered sequences (docs/cli.md "batch", docs/farm.md): the pipelined
// read -> composite -> write loop over Frame (decalcomp/frame.hpp) with resume and keep-going,
// spread over one or several OpenCL devices.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/beauty.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/exr_chunks.hpp"
#include "decalcomp/frame_pattern.hpp"
#include "decalcomp/shard.hpp"

namespace decalcomp {

struct BatchRequest {
    std::string input;   // frame pattern of the G-buffer EXRs (frames are discovered from it)
    std::vector<std::string> extra_inputs;        // further positional EXR patterns, pooled with `input`
    std::map<Attribute, std::string> pass_files;  // --pass ATTR=PATTERN (a path without a token: every frame)
    std::string output;   // frame pattern of the outputs, or a folder (a pattern may name one: out.####/)
    std::string preview;  // optional frame pattern of PNG previews
    std::string contact_sheet;  // optional PNG of every frame's thumbnail (contact_sheet.hpp); per shard
    std::string frames;  // range spec; empty = every frame whose input exists
    std::string scene;   // decal scene JSON (may animate decals over frames)
    std::string ocio_config;  // OpenColorIO config for the scene's colour spaces ("" = $OCIO)
    std::string camera;  // sidecar pattern or one sidecar; empty = header / solve
    std::string cameras; // per-frame cameras file
    std::string device;  // OpenCL devices: a selector, several separated by ',', or "all" (selectDevices)
    MappingOptions mapping;
    BeautyOptions beauty;  // --beauty, --relight (FrameOptions::beauty)
    std::optional<PixelFilter> pixel_filter;  // --pixel-filter (FrameOptions::pixel_filter)
    bool pixel_filter_fast = false;           // --pixel-filter auto:fast (FrameOptions::pixel_filter_fast)
    std::optional<bool> uv_v_down;            // --uv-origin (FrameOptions::uv_v_down)
    bool overwrite_input = false;
    bool force = false;  // composite frames that already hold this scene (FrameTargets::force)
    bool resume = false;      // skip frames whose output exists (complete: writes are atomic)
    bool keep_going = false;  // a failed frame does not stop the batch
    std::optional<Shard> shard;      // explicit --shard; wins over the environment
    bool shard_from_environment = true;  // take the shard from a Slurm job array when not explicit
    EnvironmentLookup getenv;        // for tests; default ::getenv
    ShardMode shard_mode = ShardMode::Interleaved;
    int exr_threads = 0;        // OpenEXR's global decode/encode pool; 0 = hardware threads
    int queue_depth = 2;        // frames waiting between stages (memory bound)
    int composite_workers = 0;  // compositing threads per device, each with its own Compositor; 0: by
                                // the machine (defaultCompositeWorkers)
    bool io_only = false;       // read and write without compositing (I/O cost, for benchmarks)
    bool binned = true;
};

// The frames a batch will handle, after the range, discovery and sharding.
struct BatchPlan {
    std::vector<int> frames;  // this shard's, in processing order
    int range_frames = 0;     // frames in the whole range, before sharding
    Shard shard;
    ShardMode shard_mode = ShardMode::Interleaved;
    std::string shard_source;  // "--shard", "Slurm array (SLURM_ARRAY_TASK_ID=3, ...)", or "none"
    FramePattern input;
    std::string output;  // as requested: a pattern, or a folder
    std::string outputAt(int frame) const;  // the frame's output file, or its folder
    bool outputIsFolder() const;
};
// Throws Error(Usage/Input) for bad patterns, ranges or shards.
BatchPlan planBatch(const BatchRequest& request);

enum class FrameStatus { Written, Skipped, Failed };

struct FrameResult {
    int frame = 0;
    FrameStatus status = FrameStatus::Written;
    std::string output;
    std::string message;  // the error, for failed frames
    std::optional<ErrorKind> kind;  // of a failed frame's error; nullopt: internal error (a bug)
};

struct BatchProgress {
    int total = 0;  // frames in this shard
    int written = 0, skipped = 0, failed = 0;
    double elapsed_s = 0.0;
    int finished() const { return written + skipped + failed; }
};

// Where a batch's time went: thread time summed over frames, per stage (for --timing).
struct BatchTimings {
    double read_s = 0;        // Frame::read (decode on the codecs' pool), reader thread
    double prepare_s = 0;     // Frame::prepare: channel mapping, float planes, camera, checks, masks
    double composite_s = 0;   // Frame::composite, wall time (host packing, transfers, kernels, store)
    double kernels_ms = 0;    // of which device kernel time (profiling events)
    double encode_s = 0;      // Frame::stageOutputs (encode on the codecs' pool into temporaries), workers
    double write_s = 0;       // Frame::commitOutputs (renames into place, in frame order), writer thread
    double read_wait_s = 0;   // reader blocked on a full queue (compositing or writing is slower)
    double write_idle_s = 0;  // writer waiting for frames (reading or compositing is slower)
    // CPU time: prepare and composite on the workers' own threads (a device driver that spins
    // while it waits counts here); the chunk codecs on every thread that ran them.
    double prepare_cpu_s = 0, composite_cpu_s = 0, decode_cpu_s = 0, encode_cpu_s = 0;
};

struct BatchReport {
    BatchPlan plan;
    BatchTimings timings;
    ChunkWriteStats chunks;  // summed over the written frames' outputs (FrameReport::chunks_*)
    std::vector<std::string> devices;  // names of the devices used; empty for io_only
    int workers_per_device = 0;        // compositing (for io_only: encoding) threads per device
    std::string camera_source;  // FrameCameras::describe()
    BatchProgress progress;
    std::vector<FrameResult> failures;  // in frame (plan) order
    std::optional<int> stopped_at;      // the failed frame that stopped the batch (without keep_going)
    std::vector<std::string> warnings;  // distinct warnings, each as "frames 1-40: ..." (missing channels, masks)
    std::vector<std::string> beauty;    // "frames 1-40: rebuilt ViewLayer.Combined from ..." (FrameReport::beauty)
    std::vector<std::string> pixel_filter;  // "frames 1-40: blackman-harris:3 (profile blender)"
    std::string contact_sheet;  // the sheet written (BatchRequest::contact_sheet for this shard), or ""
};

// Compositing threads per device when BatchRequest::composite_workers is 0: a worker prepares,
// composites and encodes a frame while the reader decodes the next, and takes about four times as
// long (docs/benchmarks.md), so a quarter of the hardware threads, shared among the devices, keeps
// the reader busy; at least 2 (one frame's host work overlaps another's kernels), at most 8 (each
// holds a frame in memory).
int defaultCompositeWorkers(unsigned hardware_threads, std::size_t devices);

// Called on the thread that called runBatch, in frame (plan) order.
class BatchObserver {
public:
    virtual ~BatchObserver() = default;
    virtual void started(const BatchReport&) {}
    virtual void frameFinished(const FrameResult&, const BatchProgress&) {}
    virtual void finished(const BatchReport&) {}
    // From a thread of a device's, while a kernel build runs longer than slowBuildNoticeAfter()
    // (ComputeDevice::setSlowBuildNotice): the line to show.
    virtual void slowBuild(const std::string&) {}
};

// Runs the batch: scene, textures and kernels are set up once; one thread reads (frame N+1), the
// compositing workers shade (frame N) and one thread writes (frame N-1), with bounded queues in
// between, while the codecs' thread pool decodes and encodes. Frames are written and reported in
// plan order. Without keep_going every input of the range must exist before anything starts
// (else Error(Input), nothing written), and the first failing frame stops the batch: every frame
// before it is written, none after it, and the observer's finished() sees the counts before its
// Error is thrown. An exception from the observer stops the batch too, and is rethrown: a frame
// is committed only once the observer has returned for every frame before the previous one, so at
// most the frame after the one being reported is written. With keep_going the report lists the
// failures. Stale temporaries of this shard's outputs (left by a killed run) are removed first;
// every output is written to a temporary and renamed, so no partial file is left. Set-up errors
// throw.
BatchReport runBatch(const BatchRequest& request, BatchObserver* observer = nullptr);

}  // namespace decalcomp
