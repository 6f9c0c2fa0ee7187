// The batch loop over Frame: one reader thread, compositing workers (per device) and one writer
// thread joined by bounded queues, with the codecs' thread pool (decoding first) inside each
// read and write. The workers also encode their frames into temporaries; the writer renames them
// into place in plan order, so where a batch stops does not depend on which worker was faster.
#include "decalcomp/batch.hpp"

#include <OpenEXR/ImfThreading.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include "batch/batch_files.hpp"
#include "core/thread_cpu_time.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/contact_sheet.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/frame.hpp"
#include "decalcomp/frame_cameras.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp {

namespace fs = std::filesystem;
using batch::pathAt;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double threadCpuSeconds() { return 1e-9 * double(threadCpuNs()); }

// Adds the time from construction to destruction to `total`, and this thread's CPU time to `cpu`.
struct StageTimer {
    double& total;
    double* cpu = nullptr;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    double cpu_start = cpu ? threadCpuSeconds() : 0.0;
    ~StageTimer() {
        total += secondsSince(start);
        if (cpu) *cpu += threadCpuSeconds() - cpu_start;
    }
};

// A FIFO of at most `capacity` items. close(): no more pushes, pops drain what is left;
// cancel(): drop everything, pushes and pops return at once.
template <typename T>
class BoundedQueue {
public:
    explicit BoundedQueue(std::size_t capacity) : capacity_(std::max<std::size_t>(capacity, 1)) {}

    bool push(T item) {
        std::unique_lock lock(mutex_);
        not_full_.wait(lock, [&] { return closed_ || items_.size() < capacity_; });
        if (closed_) return false;
        items_.push_back(std::move(item));
        not_empty_.notify_one();
        return true;
    }

    std::optional<T> pop() {
        std::unique_lock lock(mutex_);
        not_empty_.wait(lock, [&] { return closed_ || !items_.empty(); });
        if (items_.empty()) return std::nullopt;
        T item = std::move(items_.front());
        items_.pop_front();
        not_full_.notify_one();
        return item;
    }

    void close() {
        std::lock_guard lock(mutex_);
        closed_ = true;
        not_full_.notify_all();
        not_empty_.notify_all();
    }

    void cancel() {
        std::lock_guard lock(mutex_);
        closed_ = true;
        items_.clear();
        not_full_.notify_all();
        not_empty_.notify_all();
    }

private:
    std::size_t capacity_;
    std::mutex mutex_;
    std::condition_variable not_full_, not_empty_;
    std::deque<T> items_;
    bool closed_ = false;
};

// A frame on its way through the pipeline.
struct Job {
    std::size_t index = 0;  // position in the plan: the writer finishes frames in this order
    int frame = 0;
    std::string output;  // for reports: the output pattern's path (or folder)
    std::unique_ptr<Frame> work;
    std::optional<FrameResult> finished;  // skipped, or failed before its write: nothing to write
    std::optional<Thumbnail> thumbnail;   // for the contact sheet, taken once the frame is composited
};

// The long side of a contact sheet's thumbnails, in pixels.
constexpr int kThumbnailSize = 256;

FrameResult failure(int frame, const std::string& output, const std::exception_ptr& error) {
    FrameResult r;
    r.frame = frame;
    r.output = output;
    r.status = FrameStatus::Failed;
    try {
        std::rethrow_exception(error);
    } catch (const Error& e) {
        r.kind = e.kind();
        r.message = e.what();
    } catch (const std::exception& e) {
        r.message = std::string("internal error: ") + e.what();
    } catch (...) {
        r.message = "internal error: unknown exception";
    }
    return r;
}

// How far the writer may run ahead of the observer: it commits the frame at plan position i only
// once the observer has returned for the frames before i - 1. An observer that throws (a library
// caller stopping the batch from its progress callback) then leaves at most the frame after the
// one it was told of written, whatever the timing. The observer runs on the caller's thread and
// returns at once in the CLI, so the writer does not wait on it in practice.
class ObserverLag {
public:
    bool waitToCommit(std::size_t position) {  // false once cancelled
        std::unique_lock lock(mutex_);
        returned_.wait(lock, [&] { return cancelled_ || observed_ + 1 >= position; });
        return !cancelled_;
    }

    void observed() {
        std::lock_guard lock(mutex_);
        ++observed_;
        returned_.notify_all();
    }

    void cancel() {
        std::lock_guard lock(mutex_);
        cancelled_ = true;
        returned_.notify_all();
    }

private:
    std::mutex mutex_;
    std::condition_variable returned_;
    std::size_t observed_ = 0;  // frames the observer has returned for
    bool cancelled_ = false;
};

// At most `limit` frames between the reader taking one and the writer finishing it: frames that
// wait for an earlier one to be written first stay bounded, and so does memory.
class InFlightLimit {
public:
    explicit InFlightLimit(int limit) : free_(std::max(limit, 1)) {}

    bool acquire() {  // false once cancelled
        std::unique_lock lock(mutex_);
        freed_.wait(lock, [&] { return cancelled_ || free_ > 0; });
        if (cancelled_) return false;
        --free_;
        return true;
    }

    void release() {
        std::lock_guard lock(mutex_);
        ++free_;
        freed_.notify_one();
    }

    void cancel() {
        std::lock_guard lock(mutex_);
        cancelled_ = true;
        freed_.notify_all();
    }

private:
    std::mutex mutex_;
    std::condition_variable freed_;
    int free_;
    bool cancelled_ = false;
};

// Hands jobs out in plan order, whatever order they arrive in.
class InOrder {
public:
    void add(Job job) {
        const std::size_t index = job.index;
        waiting_.emplace(index, std::move(job));
    }

    std::optional<Job> next() {
        const auto it = waiting_.find(next_);
        if (it == waiting_.end()) return std::nullopt;
        Job job = std::move(it->second);
        waiting_.erase(it);
        ++next_;
        return job;
    }

private:
    std::map<std::size_t, Job> waiting_;
    std::size_t next_ = 0;
};

// One device's compositors, one per worker, each holding the scene's textures.
struct DeviceWorkers {
    std::unique_ptr<ComputeDevice> device;
    std::vector<std::unique_ptr<Compositor>> compositors;
};

// "frame 7", "frames 1-40", "frames 1-3, 7, 10-20x2": runs of one step (three frames or more)
// as --frames writes them; at most ten pieces, then how many frames are left.
std::string describeFrames(const std::set<int>& frames) {
    const std::vector<int> f(frames.begin(), frames.end());
    if (f.size() == 1) return fmt::format("frame {}", f.front());
    const auto gap = [&](std::size_t k) { return static_cast<long long>(f[k]) - f[k - 1]; };
    std::vector<std::string> pieces;
    std::size_t i = 0;
    while (i < f.size() && pieces.size() < 10) {
        std::size_t j = i + 1;
        const long long step = j < f.size() ? gap(j) : 0;
        while (j < f.size() && gap(j) == step) ++j;
        const std::size_t run = j - i;
        if (run >= 3 || (run == 2 && step == 1)) {
            pieces.push_back(step == 1 ? fmt::format("{}-{}", f[i], f[j - 1])
                                       : fmt::format("{}-{}x{}", f[i], f[j - 1], step));
            i = j;
        } else {
            pieces.push_back(std::to_string(f[i]));
            ++i;
        }
    }
    std::string text = fmt::format("frames {}", fmt::join(pieces, ", "));
    if (i < f.size()) text += fmt::format(" and {} more", f.size() - i);
    return text;
}

// Distinct warnings of all frames, reported once after the batch, each with the frames it came
// from ("frames 1-40: ..."), in the order of their first frame.
class WarningSet {
public:
    void add(int frame, const std::vector<std::string>& warnings) {
        std::lock_guard lock(mutex_);
        for (const std::string& warning : warnings) frames_[warning].insert(frame);
    }
    std::vector<std::string> list() {
        std::lock_guard lock(mutex_);
        std::vector<std::pair<int, std::string>> ordered;
        for (const auto& [warning, frames] : frames_)
            ordered.emplace_back(*frames.begin(), describeFrames(frames) + ": " + warning);
        std::stable_sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        std::vector<std::string> out;
        for (auto& [first, text] : ordered) out.push_back(std::move(text));
        return out;
    }

private:
    std::mutex mutex_;
    std::map<std::string, std::set<int>> frames_;  // warning -> frames
};

// The three stages of a batch and what they share. The reader takes frames in plan order, the
// workers composite them in whatever order they finish, and the writer writes and reports them
// in plan order again: a batch that stops at a failing frame has written every frame before it
// and none after it, whatever the timing.
class Pipeline {
public:
    struct SetUp {  // once per batch, shared by every frame
        const BatchRequest& request;
        const BatchPlan& plan;
        const FrameCameras& cameras;
        const DecalScene& scene;
        std::vector<DeviceWorkers>& devices;
        FrameOptions options;
        int workers_per_device = 1;
    };

    explicit Pipeline(SetUp setup)
        : s_(std::move(setup)),
          // --io-only encodes on as many workers as compositing on one device: the same pipeline, without decals
          workers_(s_.request.io_only ? s_.workers_per_device : int(s_.devices.size()) * s_.workers_per_device),
          depth_(std::size_t(std::max(1, s_.request.queue_depth))),
          to_composite_(depth_),
          to_write_(depth_),
          in_flight_(batch::framesInFlight(s_.request, workers_)),
          timings_(std::size_t(workers_) + 2),
          sheet_(int(s_.plan.frames.size())) {}

    ~Pipeline() {  // on an exception in the observer: stop and join the threads
        cancel();
        for (std::thread& t : threads_)
            if (t.joinable()) t.join();
    }

    // Runs the frames; reports each to `watch` on this thread, in plan order. Returns the failure
    // that stopped the batch (without keep_going), if one did.
    std::optional<FrameResult> run(BatchReport& report, BatchObserver& watch);
    std::vector<std::string> warnings() { return warnings_.list(); }
    std::vector<std::string> beautyNotes() { return beauty_notes_.list(); }
    std::vector<std::string> pixelFilterNotes() { return filter_notes_.list(); }
    BatchTimings timings() const;
    const ChunkWriteStats& chunks() const { return chunks_; }  // after run()
    const ContactSheet& contactSheet() const { return sheet_; }  // after run(): the written frames' thumbnails

private:
    SetUp s_;
    const int workers_;
    const std::size_t depth_;
    BoundedQueue<Job> to_composite_, to_write_;
    BoundedQueue<FrameResult> results_{std::size_t(-1) / 2};
    InFlightLimit in_flight_;
    ObserverLag observer_lag_;
    std::atomic<int> producers_{0};  // of to_write_: the reader and the workers
    SequenceConventions sequence_;  // depth and normal readings settled once for the sequence
    WarningSet warnings_;
    WarningSet beauty_notes_;  // what the beauty step did, said once per distinct summary
    WarningSet filter_notes_;  // the pixel filter each frame was integrated over, likewise
    std::vector<BatchTimings> timings_;  // reader, writer, then one per worker; summed at the end
    ChunkWriteStats chunks_;             // the writer thread's
    ContactSheet sheet_;                 // likewise
    std::vector<std::thread> threads_;

    void cancel() {
        to_composite_.cancel();
        to_write_.cancel();
        in_flight_.cancel();
        observer_lag_.cancel();
    }
    void producerDone() {
        if (--producers_ == 0) to_write_.close();
    }
    void readFrames();
    Job readFrame(std::size_t index);
    void compositeFrames(int worker);
    void compositeFrame(Job& job, Compositor* compositor, BatchTimings& timings);
    void writeFrames();
    FrameResult writeFrame(Job& job);
};

void Pipeline::readFrames() {
    BatchTimings& timings = timings_[0];
    for (std::size_t i = 0; i < s_.plan.frames.size(); ++i) {
        if (!in_flight_.acquire()) break;
        Job job = readFrame(i);
        BoundedQueue<Job>& next = job.finished ? to_write_ : to_composite_;
        StageTimer t{timings.read_wait_s};
        if (!next.push(std::move(job))) break;
    }
    to_composite_.close();
    producerDone();
}

Job Pipeline::readFrame(std::size_t index) {
    const BatchRequest& request = s_.request;
    Job job;
    job.index = index;
    job.frame = s_.plan.frames[index];
    job.output = s_.plan.outputAt(job.frame);
    if (request.resume && batch::frameDone(request, s_.plan, job.frame)) {
        job.finished = FrameResult{job.frame, FrameStatus::Skipped, job.output, "", std::nullopt};
        return job;
    }
    try {
        FrameSources sources = batch::frameSources(request, s_.plan, job.frame);
        sources.camera = s_.cameras.explicitCamera(job.frame);
        sources.camera_file = s_.cameras.cameraFile(job.frame);
        FrameTargets targets{job.output, request.preview.empty() ? "" : pathAt(request.preview, job.frame),
                             request.overwrite_input, !request.contact_sheet.empty(), request.force};
        FrameOptions frame_options = s_.options;
        frame_options.frame_number = double(job.frame);
        job.work = std::make_unique<Frame>(std::move(sources), std::move(targets), std::move(frame_options));
        StageTimer t{timings_[0].read_s};
        // Only the chunks the frame's decals can reach; --io-only reads and re-encodes every chunk:
        // the I/O of a frame whose decals change everything, the yardstick of the batch bench.
        if (request.io_only) job.work->readAsIfEverythingChanged();
        else job.work->read(&s_.scene);
    } catch (...) {
        job.work.reset();
        job.finished = failure(job.frame, job.output, std::current_exception());
    }
    return job;
}

void Pipeline::compositeFrames(int worker) {
    BatchTimings& timings = timings_[std::size_t(worker) + 2];
    Compositor* compositor = s_.request.io_only ? nullptr
                                                : s_.devices[std::size_t(worker / s_.workers_per_device)]
                                                      .compositors[std::size_t(worker % s_.workers_per_device)]
                                                      .get();
    while (auto job = to_composite_.pop()) {
        compositeFrame(*job, compositor, timings);
        if (!to_write_.push(std::move(*job))) break;
    }
    producerDone();
}

void Pipeline::compositeFrame(Job& job, Compositor* compositor, BatchTimings& timings) {
    try {
        {
            StageTimer t{timings.prepare_s, &timings.prepare_cpu_s};
            job.work->prepare(s_.scene, &sequence_);  // empty for --io-only: nothing to composite
        }
        if (compositor) {
            StageTimer t{timings.composite_s, &timings.composite_cpu_s};
            job.work->composite(*compositor);
            timings.kernels_ms += job.work->report().stats.totalKernelMs();
        }
        if (!s_.request.contact_sheet.empty()) job.thumbnail = makeThumbnail(job.work->gbuffer(), kThumbnailSize);
        warnings_.add(job.frame, job.work->report().warnings);  // prepare's and composite's
        if (job.work->report().beauty.rebuilt) beauty_notes_.add(job.frame, {job.work->report().beauty.summary});
        if (!job.work->report().pixel_filter.empty()) filter_notes_.add(job.frame, {job.work->report().pixel_filter});
        // Encoded here, on each worker, into temporaries; the writer only renames them, in frame order.
        // With one writer encoding, it was the batch's bottleneck (docs/decisions.md).
        StageTimer t{timings.encode_s};
        job.work->stageOutputs();
    } catch (...) {
        job.work.reset();
        job.finished = failure(job.frame, job.output, std::current_exception());
    }
}

void Pipeline::writeFrames() {
    BatchTimings& timings = timings_[1];
    InOrder in_order;
    bool stopped = false;
    while (!stopped) {
        std::optional<Job> arrived;
        {
            StageTimer t{timings.write_idle_s};
            arrived = to_write_.pop();
        }
        if (!arrived) break;
        in_order.add(std::move(*arrived));
        while (!stopped) {
            std::optional<Job> job = in_order.next();
            if (!job) break;
            bool may_commit = false;
            {
                StageTimer t{timings.write_idle_s};
                may_commit = observer_lag_.waitToCommit(job->index);
            }
            if (!may_commit) {  // the batch was cancelled: the frame is dropped unwritten
                stopped = true;
                break;
            }
            const FrameResult result = job->finished ? *job->finished : writeFrame(*job);
            if (result.status == FrameStatus::Written && job->thumbnail) sheet_.add(job->index, std::move(*job->thumbnail));
            job.reset();  // the frame's planes go before the next one is taken
            stopped = result.status == FrameStatus::Failed && !s_.request.keep_going;
            if (stopped) cancel();  // frames after the failure are dropped unwritten
            results_.push(result);
            in_flight_.release();
        }
    }
    results_.close();
}

FrameResult Pipeline::writeFrame(Job& job) {
    try {
        StageTimer t{timings_[1].write_s};
        const std::vector<std::string>& written = job.work->commitOutputs();
        const FrameReport& frame = job.work->report();
        chunks_ += ChunkWriteStats{frame.chunks_copied, frame.chunks_reencoded, frame.pixels_reencoded};
        return FrameResult{job.frame, FrameStatus::Written, written.size() == 1 ? written.front() : job.output, "",
                           std::nullopt};
    } catch (...) {
        return failure(job.frame, job.output, std::current_exception());
    }
}

std::optional<FrameResult> Pipeline::run(BatchReport& report, BatchObserver& watch) {
    const auto start = std::chrono::steady_clock::now();
    producers_ = 1 + workers_;
    threads_.emplace_back([this] { readFrames(); });
    for (int w = 0; w < workers_; ++w) threads_.emplace_back([this, w] { compositeFrames(w); });
    threads_.emplace_back([this] { writeFrames(); });

    std::optional<FrameResult> stopped_by;
    BatchProgress& p = report.progress;
    while (auto result = results_.pop()) {
        if (result->status == FrameStatus::Written) ++p.written;
        else if (result->status == FrameStatus::Skipped) ++p.skipped;
        else {
            ++p.failed;
            report.failures.push_back(*result);
            if (!s_.request.keep_going) stopped_by = *result;
        }
        p.elapsed_s = secondsSince(start);
        watch.frameFinished(*result, p);
        observer_lag_.observed();
    }
    for (std::thread& t : threads_) t.join();
    p.elapsed_s = secondsSince(start);
    return stopped_by;
}

BatchTimings Pipeline::timings() const {
    BatchTimings sum;
    for (const BatchTimings& t : timings_) {
        sum.read_s += t.read_s, sum.prepare_s += t.prepare_s, sum.composite_s += t.composite_s;
        sum.kernels_ms += t.kernels_ms, sum.encode_s += t.encode_s, sum.write_s += t.write_s;
        sum.read_wait_s += t.read_wait_s, sum.write_idle_s += t.write_idle_s;
        sum.prepare_cpu_s += t.prepare_cpu_s, sum.composite_cpu_s += t.composite_cpu_s;
    }
    return sum;
}

unsigned hardwareThreads() { return std::max(1u, std::thread::hardware_concurrency()); }

int workersPerDevice(const BatchRequest& request, std::size_t devices) {
    return request.composite_workers > 0 ? request.composite_workers
                                         : defaultCompositeWorkers(hardwareThreads(), devices);
}

// The devices --device selects, with a compositor per worker each (report.workers_per_device).
std::vector<DeviceWorkers> setUpDevices(const BatchRequest& request, const DecalScene& scene, BatchReport& report,
                                        BatchObserver& watch) {
    const std::chrono::milliseconds notice_after = slowBuildNoticeAfter();
    std::vector<DeviceInfo> selected = selectDevices(request.device);
    report.workers_per_device = workersPerDevice(request, selected.size());
    std::vector<DeviceWorkers> devices;
    for (DeviceInfo& info : selected) {
        DeviceWorkers& d = devices.emplace_back();
        d.device = std::make_unique<ComputeDevice>(std::move(info));
        d.device->setSlowBuildNotice(notice_after, [&watch](const std::string& m) { watch.slowBuild(m); });
        report.devices.push_back(d.device->info().name);
        for (int w = 0; w < report.workers_per_device; ++w) {
            d.compositors.push_back(std::make_unique<Compositor>(*d.device));
            d.compositors.back()->setScene(scene);
        }
    }
    return devices;
}

}  // namespace

int defaultCompositeWorkers(unsigned hardware_threads, std::size_t devices) {
    const std::size_t share = hardware_threads / (4 * std::max<std::size_t>(devices, 1));
    return int(std::clamp<std::size_t>(share, 2, 8));
}

std::string BatchPlan::outputAt(int frame) const { return pathAt(output, frame); }
bool BatchPlan::outputIsFolder() const { return isOutputFolder(output); }

BatchPlan planBatch(const BatchRequest& request) {
    BatchPlan plan;
    plan.input = FramePattern(request.input);
    plan.output = request.output;
    if (!FramePattern::hasToken(request.output) && !isOutputFolder(request.output))
        throw Error(ErrorKind::Usage, fmt::format("-o {}: give a frame pattern (out.####.exr) or a folder (out/), so "
                                                  "frames do not overwrite each other",
                                                  request.output));
    if (FramePattern::hasToken(request.output)) FramePattern{request.output};  // exactly one token
    if (!request.preview.empty()) FramePattern{request.preview};                // one preview per frame
    for (const std::string& extra : request.extra_inputs)
        if (FramePattern::hasToken(extra)) FramePattern{extra};
    for (const auto& [attribute, pass] : request.pass_files)
        if (FramePattern::hasToken(pass)) FramePattern{pass};
    const std::vector<int> frames = request.frames.empty() ? discoverFrames(plan.input) : parseFrameRange(request.frames);
    plan.range_frames = int(frames.size());
    plan.shard_mode = request.shard_mode;
    plan.shard_source = "none";
    if (request.shard) {
        plan.shard = *request.shard;
        plan.shard_source = "--shard";
    } else if (request.shard_from_environment) {
        const EnvironmentLookup lookup =
            request.getenv ? request.getenv : EnvironmentLookup([](const char* name) { return std::getenv(name); });
        if (auto shard = shardFromSlurmEnvironment(lookup)) {
            plan.shard = *shard;
            plan.shard_source = fmt::format("Slurm array task (SLURM_ARRAY_TASK_ID={})", lookup("SLURM_ARRAY_TASK_ID"));
        }
    }
    plan.frames = shardFrames(frames, plan.shard, plan.shard_mode);
    return plan;
}

BatchReport runBatch(const BatchRequest& request, BatchObserver* observer) {
    BatchObserver silent;
    BatchObserver& watch = observer ? *observer : silent;
    BatchReport report;
    report.plan = planBatch(request);
    const BatchPlan& plan = report.plan;
    report.progress.total = int(plan.frames.size());

    // ---- set-up, once per batch; nothing is written before the range's inputs are all there ----
    const FrameCameras cameras(request.camera, request.cameras);
    report.camera_source = cameras.describe();
    if (!request.keep_going) batch::requireRangeInputs(request, plan, cameras);
    DecalScene scene;
    std::vector<DeviceWorkers> devices;
    if (!request.io_only) {
        scene = loadScene(request.scene, SceneOptions{request.ocio_config});
        if (!plan.frames.empty()) devices = setUpDevices(request, scene, report, watch);
    }
    // After the scene: decoding its EXR textures through OpenImageIO may change the global count.
    Imf::setGlobalThreadCount(request.exr_threads > 0 ? request.exr_threads : int(hardwareThreads()));
    const std::string sheet_path =
        request.contact_sheet.empty() ? "" : contactSheetPath(request.contact_sheet, plan.shard.index, plan.shard.count);
    if (!sheet_path.empty()) batch::checkContactSheet(request, plan, scene, sheet_path);
    batch::createOutputFolders(request, plan);
    batch::removeStaleTemporaries(request, plan);
    FrameOptions options;
    options.mapping = request.mapping;
    options.beauty = request.beauty;
    options.pixel_filter = request.pixel_filter;
    options.pixel_filter_fast = request.pixel_filter_fast;
    options.uv_v_down = request.uv_v_down;
    options.compositing.binned = request.binned;
    options.compositing.host_threads = 1;  // the workers' frames are the parallelism (CompositeOptions)
    options.label = request.input;  // warnings name the sequence, so each is reported once

    // ---- the frames ----
    if (devices.empty()) report.workers_per_device = workersPerDevice(request, 0);  // io_only, or no frames
    Pipeline pipeline({request, plan, cameras, scene, devices, options, report.workers_per_device});
    watch.started(report);
    const CodecCpu codecs_before = codecCpuSeconds();
    const std::optional<FrameResult> stopped_by = pipeline.run(report, watch);
    const CodecCpu codecs_after = codecCpuSeconds();
    if (stopped_by) report.stopped_at = stopped_by->frame;
    report.warnings = pipeline.warnings();
    report.beauty = pipeline.beautyNotes();
    report.pixel_filter = pipeline.pixelFilterNotes();
    report.timings = pipeline.timings();
    report.timings.decode_cpu_s = codecs_after.decode_s - codecs_before.decode_s;
    report.timings.encode_cpu_s = codecs_after.encode_s - codecs_before.encode_s;
    report.chunks = pipeline.chunks();
    // The sheet shows a finished run (failed frames of --keep-going as grey cells); a stopped run
    // writes none, as it writes no frame after the failure.
    if (!sheet_path.empty() && !stopped_by && !plan.frames.empty()) {
        pipeline.contactSheet().write(sheet_path);
        report.contact_sheet = sheet_path;
    }
    watch.finished(report);
    if (stopped_by) {
        if (stopped_by->kind) throw Error(*stopped_by->kind, stopped_by->message);
        throw std::runtime_error(stopped_by->message);
    }
    return report;
}

}  // namespace decalcomp
