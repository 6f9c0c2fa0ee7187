#pragma once
// Batch post-processing of rendered sequences (docs/cli.md "batch", docs/farm.md): frame patterns
// and ranges, per-frame cameras, shards of a range for a farm, and the pipelined
// read -> composite -> write loop with resume and keep-going.
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

// ---- frame numbers and file-name patterns ----

// "1-240", "1-240x2" (every 2nd), "1,5,10-20", "-5--1": frames in the order given, each once.
// Throws Error(Usage) naming the bad part of `spec`.
std::vector<int> parseFrameRange(const std::string& spec);

// A path with exactly one frame token: a run of '#' (as many digits, zero-padded: "####" -> 0007)
// or a printf-style "%d" / "%0Nd". Negative frames print a '-' before the padded digits, as printf.
class FramePattern {
public:
    FramePattern() = default;
    explicit FramePattern(const std::string& pattern);  // Error(Usage) without exactly one token
    static bool hasToken(const std::string& text);       // any '#' run or %d / %0Nd

    std::string path(int frame) const;
    // The frame a path stands for, when it is exactly this pattern's path for that frame.
    std::optional<int> match(const std::string& path) const;
    const std::string& text() const { return text_; }

private:
    std::string text_, prefix_, suffix_;
    int width_ = 0;
};

// Every frame whose file exists, by listing the folder of `input` (the token must be in the file
// name). Sorted; throws Error(Input) when none matches.
std::vector<int> discoverFrames(const FramePattern& input);

// ---- shards: one machine's part of a range ----

enum class ShardMode { Interleaved, Contiguous };
const char* shardModeName(ShardMode mode);

struct Shard {
    int index = 1;  // 1-based: 1..count (as `split -n l/K/N`)
    int count = 1;
};

// "I/N" with 1 <= I <= N. Throws Error(Usage).
Shard parseShard(const std::string& spec);

// From a Slurm job array: index = (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN) / step + 1 (step from
// SLURM_ARRAY_TASK_STEP, default 1), count = SLURM_ARRAY_TASK_COUNT. nullopt outside an array job;
// Error(Usage) when the variables are inconsistent (non-numeric, index out of range).
using EnvironmentLookup = std::function<const char*(const char*)>;
std::optional<Shard> shardFromSlurmEnvironment(const EnvironmentLookup& getenv);

// Interleaved: positions index-1, index-1+count, ...; contiguous: the index-th of `count` runs of
// (nearly) equal length, earlier runs one longer when the sizes do not divide.
std::vector<int> shardFrames(const std::vector<int>& frames, const Shard& shard, ShardMode mode);

// ---- per-frame cameras ----

// Where each frame's camera comes from, in order: a per-frame cameras file (`cameras`), a sidecar
// pattern or one sidecar for every frame (`camera`), else nothing (the frame's header, then a
// camera solved from its position pass, as `composite`).
class FrameCameras {
public:
    FrameCameras() = default;
    // Loads a fixed sidecar or the per-frame file up front; Error(Input) naming file and field.
    FrameCameras(const std::string& camera, const std::string& cameras);
    // nullopt: no explicit camera, use the header / solve. Error(Input) when the frame has none in
    // the per-frame file or its sidecar cannot be read.
    std::optional<Camera> explicitCamera(int frame) const;
    std::string describe() const;

private:
    std::optional<Camera> fixed_;
    std::optional<FramePattern> pattern_;
    std::map<int, Camera> per_frame_;
    std::string per_frame_file_;
};

// One JSON file with a camera per frame (docs/cli.md): {"projection": [[...]] (optional default),
// "frames": {"1": {"world_to_camera": [[...]], "projection": [[...]]}, ...}} or "frames" as an
// array of objects with a "frame" number. Throws Error(Input) naming the file and JSON path.
std::map<int, Camera> loadPerFrameCameras(const std::string& path);

// ---- the batch ----

struct BatchRequest {
    std::string input;   // frame pattern of the G-buffer EXRs
    std::string output;  // frame pattern of the outputs
    std::string frames;  // range spec; empty = every frame whose input exists
    std::string scene;   // decal scene JSON (may animate decals over frames)
    std::string camera;  // sidecar pattern or one sidecar; empty = header / solve
    std::string cameras; // per-frame cameras file
    std::string device;  // OpenCL device selector
    MappingOptions mapping;
    bool overwrite_input = false;
    bool resume = false;      // skip frames whose output exists (complete: writes are atomic)
    bool keep_going = false;  // a failed frame does not stop the batch
    std::optional<Shard> shard;      // explicit --shard; wins over the environment
    bool shard_from_environment = true;  // take the shard from a Slurm job array when not explicit
    EnvironmentLookup getenv;        // for tests; default ::getenv
    ShardMode shard_mode = ShardMode::Interleaved;
    int exr_threads = 0;        // OpenEXR's global decode/encode pool; 0 = hardware threads
    int queue_depth = 2;        // frames waiting between stages (memory bound)
    int composite_workers = 2;  // compositing threads, each with its own Compositor on one device
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
    FramePattern input, output;
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
    double read_s = 0;        // readExr (decode on OpenEXR's pool), reader thread
    double map_extract_s = 0; // channel mapping, camera, float planes, depth check
    double set_scene_s = 0;   // per-frame decals of animated scenes (Compositor::setScene)
    double composite_s = 0;   // Compositor::composite, wall time (host packing, transfers, kernels)
    double kernels_ms = 0;    // of which device kernel time (profiling events)
    double store_s = 0;       // storeAttribute: the albedo back into the EXR channels
    double write_s = 0;       // writeExrAtomic (encode on OpenEXR's pool), writer thread
    double read_wait_s = 0;   // reader blocked on a full queue (compositing or writing is slower)
    double write_idle_s = 0;  // writer waiting for frames (reading or compositing is slower)
};

struct BatchReport {
    BatchPlan plan;
    BatchTimings timings;
    std::string device;         // empty for io_only
    std::string camera_source;  // FrameCameras::describe()
    BatchProgress progress;
    std::vector<FrameResult> failures;  // in the order they happened
    std::vector<std::string> warnings;  // distinct warnings over all frames (missing channels, masks)
};

// Called on the thread that called runBatch, in the order frames finish.
class BatchObserver {
public:
    virtual ~BatchObserver() = default;
    virtual void started(const BatchReport&) {}
    virtual void frameFinished(const FrameResult&, const BatchProgress&) {}
    virtual void finished(const BatchReport&) {}
};

// Runs the batch: scene, textures and kernels are set up once; one thread reads (frame N+1), the
// compositing workers shade (frame N) and one thread writes (frame N-1), with bounded queues in
// between, while OpenEXR's thread pool decodes and encodes. Stale temporaries of this shard's
// outputs (left by a killed run) are removed first. Set-up errors throw. A failed frame throws
// its Error unless keep_going, after the frames in flight are abandoned (no partial file is left:
// every output is written to a temporary and renamed). With keep_going the report lists failures.
BatchReport runBatch(const BatchRequest& request, BatchObserver* observer = nullptr);

// ---- progress ----

enum class ProgressStyle { Bar, Lines, Quiet };

// A progress bar redrawn in place (terminals), or one line per finished frame (logs), with frames
// done, frames per second and time left; Quiet prints nothing. Writes to `out` (stderr in the CLI).
class ProgressPrinter : public BatchObserver {
public:
    ProgressPrinter(std::ostream& out, ProgressStyle style);
    void started(const BatchReport& report) override;
    void frameFinished(const FrameResult& result, const BatchProgress& progress) override;
    void finished(const BatchReport& report) override;

private:
    std::ostream& out_;
    ProgressStyle style_;
    double last_draw_s_ = -1.0;
    std::size_t last_width_ = 0;
    void drawBar(const BatchProgress& progress, bool force);
};

// "12.3 fps, 0:42 left" pieces, for the printer and tests.
std::string formatDuration(double seconds);  // 0:07, 1:02:03
// Frames per second over frames actually processed (written + failed), and the time left for the rest.
double framesPerSecond(const BatchProgress& progress);
std::optional<double> secondsLeft(const BatchProgress& progress);

}  // namespace decalcomp
