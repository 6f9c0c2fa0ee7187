// The batch loop: one reader thread, compositing workers and one writer thread joined by bounded
// queues, with OpenEXR's thread pool doing the decoding and encoding inside each read and write.
#include <OpenEXR/ImfThreading.h>
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

#include "decalcomp/batch.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/masks.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp {

namespace fs = std::filesystem;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Adds the time from construction to destruction to `total`.
struct StageTimer {
    double& total;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    ~StageTimer() { total += secondsSince(start); }
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

struct Job {
    int frame = 0;
    std::string input, output;
    std::vector<ExrImage> files;  // the frame's EXR (one file per frame today)
};

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

// writeExrAtomic writes ".NAME.tmp-PID" beside NAME (src/io/exr_file.cpp). A run killed while
// writing leaves one behind; the next run removes those of its own frames (never another shard's).
void removeStaleTemporaries(const BatchPlan& plan) {
    std::map<fs::path, std::set<std::string>> names;  // folder -> output file names
    for (int frame : plan.frames) {
        const fs::path out(plan.output.path(frame));
        names[out.parent_path()].insert(out.filename().string());
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

void createOutputFolders(const BatchPlan& plan) {
    std::set<fs::path> folders;
    for (int frame : plan.frames) folders.insert(fs::path(plan.output.path(frame)).parent_path());
    for (const fs::path& folder : folders) {
        if (folder.empty()) continue;
        std::error_code ec;
        fs::create_directories(folder, ec);
        if (ec) throw outputError(fmt::format("{}: cannot create the output folder: {}", folder.string(), ec.message()));
    }
}

// State the compositing workers share: read-only inputs, and the depth convention settled once.
class FrameCompositing {
public:
    FrameCompositing(const BatchRequest& request, const DecalScene& scene, const FrameCameras& cameras)
        : request_(request), scene_(scene), cameras_(cameras), animated_(isAnimated(scene)) {}

    // Composites one frame in place (its albedo channels) with this worker's compositor.
    void composite(Job& job, Compositor& compositor, DecalScene& work_scene, BatchTimings& timings) {
        std::vector<ExrImage>& files = job.files;
        std::optional<StageTimer> timer;
        timer.emplace(timings.map_extract_s);
        ChannelMapping mapping = mapChannels(files, request_.mapping);
        if (!mapping.attributes.count(Attribute::Albedo))
            throw inputError(fmt::format("{}: no albedo channels found (profile {}); map them with --channel "
                                         "albedo=R,G,B",
                                         job.input, mapping.profile));
        addAttributeChannels(files, mapping, request_.mapping);
        const std::vector<Decal>* decals = &scene_.decals;
        if (animated_) {
            work_scene.decals = decalsAtFrame(scene_.decals, double(job.frame));
            decals = &work_scene.decals;
        }
        if (decals->empty()) return;  // nothing alive on this frame: the output is the input

        // As `composite` (src/pipeline/composite_file.cpp) does for one frame.
        GBuffer gbuffer = extractGBuffer(files, mapping);
        std::optional<Camera> camera = cameras_.explicitCamera(job.frame);
        if (!camera) camera = resolveCamera(files, gbuffer, "");  // header, else solved
        if (const std::optional<DepthConvention> settled = settledConvention()) {
            gbuffer.depth_convention = *settled;
            mapping.depth_convention = *settled;
        } else {
            const DepthCheck check = settleDepthConvention(gbuffer, mapping, *camera);
            if (check.performed || !gbuffer.has(Attribute::Position)) settle(gbuffer.depth_convention);
        }
        if (gbuffer.has(Attribute::Normal)) {  // like the depth convention: one verdict for the sequence
            if (const std::optional<NormalEncoding> settled = settledNormals()) {
                gbuffer.normal_encoding = *settled;
                mapping.normal_space = normalSpaceName(settled->space);
                mapping.normal_encoding = settled->packed ? "unsigned" : "signed";
            } else if (settleNormalEncoding(gbuffer, mapping, *camera).verdict) {
                settleNormals(gbuffer.normal_encoding);
            }
        }
        std::vector<std::string> warnings = missingAttributeWarnings(compositedAttributes(scene_), mapping, request_.input);
        evaluateMasks(files, mapping, scene_, gbuffer, &warnings);
        noteWarnings(warnings);
        // Per-frame decals replace the decals only; the textures were uploaded once.
        timer.reset();
        if (animated_) {
            StageTimer t{timings.set_scene_s};
            compositor.setDecals(work_scene.decals);
        }
        {
            StageTimer t{timings.composite_s};
            timings.kernels_ms += compositor.composite(gbuffer, *camera, CompositeOptions{request_.binned}).totalKernelMs();
        }
        StageTimer t{timings.store_s};
        for (Attribute attribute : compositedAttributes(scene_))
            if (gbuffer.has(attribute)) storeAttribute(files, mapping, attribute, gbuffer.planes.at(attribute));
    }

private:
    const BatchRequest& request_;
    const DecalScene& scene_;
    const FrameCameras& cameras_;
    const bool animated_;
    std::mutex mutex_;
    std::optional<DepthConvention> settled_;
    std::optional<NormalEncoding> settled_normals_;
    std::set<std::string> warnings_;  // distinct warnings of all frames

public:
    std::vector<std::string> warnings() {
        std::lock_guard lock(mutex_);
        return {warnings_.begin(), warnings_.end()};
    }

private:
    // The first frame whose normals fit one reading clearly settles it for the sequence.
    std::optional<NormalEncoding> settledNormals() {
        std::lock_guard lock(mutex_);
        return settled_normals_;
    }
    void settleNormals(NormalEncoding encoding) {
        std::lock_guard lock(mutex_);
        if (!settled_normals_) settled_normals_ = encoding;
    }
    void noteWarnings(const std::vector<std::string>& warnings) {
        std::lock_guard lock(mutex_);
        warnings_.insert(warnings.begin(), warnings.end());
    }

    // The planar/radial check runs until one frame could perform it (or the frames have no
    // position pass to check against); its verdict then holds for the whole sequence.
    std::optional<DepthConvention> settledConvention() {
        std::lock_guard lock(mutex_);
        return settled_;
    }
    void settle(DepthConvention convention) {
        std::lock_guard lock(mutex_);
        if (!settled_) settled_ = convention;
    }
};

}  // namespace

BatchPlan planBatch(const BatchRequest& request) {
    BatchPlan plan;
    plan.input = FramePattern(request.input);
    plan.output = FramePattern(request.output);
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

    // ---- set-up, once per batch ----
    const FrameCameras cameras(request.camera, request.cameras);
    report.camera_source = cameras.describe();
    DecalScene scene;
    std::unique_ptr<ComputeDevice> device;
    std::vector<std::unique_ptr<Compositor>> compositors;
    std::vector<DecalScene> work_scenes;  // per worker: this frame's decals (textures stay on the device)
    const int workers = std::max(1, request.composite_workers);
    if (!request.io_only) {
        scene = loadScene(request.scene);
        if (!plan.frames.empty()) {
            device = std::make_unique<ComputeDevice>(request.device);
            report.device = device->info().name;
            for (int w = 0; w < workers; ++w) {
                compositors.push_back(std::make_unique<Compositor>(*device));
                compositors.back()->setScene(scene);
                work_scenes.push_back(DecalScene{{}, {}, scene.masks});
            }
        }
    }
    // After the scene: decoding its EXR textures through OpenImageIO may change the global count.
    Imf::setGlobalThreadCount(request.exr_threads > 0 ? request.exr_threads
                                                      : int(std::max(1u, std::thread::hardware_concurrency())));
    createOutputFolders(plan);
    removeStaleTemporaries(plan);
    FrameCompositing compositing(request, scene, cameras);

    // ---- the pipeline ----
    const std::size_t depth = std::size_t(std::max(1, request.queue_depth));
    BoundedQueue<Job> to_composite(depth), to_write(depth);
    BoundedQueue<FrameResult> results(std::size_t(-1) / 2);
    std::atomic<bool> cancelled{false};
    std::atomic<int> live{0}, live_workers{workers};
    auto finishThread = [&] {
        if (--live == 0) results.close();
    };
    auto cancelAll = [&] {
        cancelled = true;
        to_composite.cancel();
        to_write.cancel();
    };
    std::vector<std::thread> threads;
    struct Joiner {
        std::vector<std::thread>& threads;
        std::function<void()> cancel;
        ~Joiner() {
            if (std::any_of(threads.begin(), threads.end(), [](const std::thread& t) { return t.joinable(); })) cancel();
            for (std::thread& t : threads)
                if (t.joinable()) t.join();
        }
    } joiner{threads, cancelAll};

    // One timings record per thread, summed after the join.
    std::vector<BatchTimings> thread_timings(std::size_t(workers) + 2);
    BatchTimings& reader_timings = thread_timings[0];
    BatchTimings& writer_timings = thread_timings[1];
    const auto start = std::chrono::steady_clock::now();
    watch.started(report);
    live = 2 + workers;
    threads.emplace_back([&] {  // reader
        for (int frame : plan.frames) {
            if (cancelled) break;
            Job job;
            job.frame = frame;
            job.input = plan.input.path(frame);
            job.output = plan.output.path(frame);
            std::error_code ec;
            if (request.resume && fs::is_regular_file(job.output, ec)) {
                results.push(FrameResult{frame, FrameStatus::Skipped, job.output, "", std::nullopt});
                continue;
            }
            try {
                checkNotOverwritingInput(job.input, job.output, request.overwrite_input);
                StageTimer t{reader_timings.read_s};
                job.files.push_back(readExr(job.input));
            } catch (...) {
                results.push(failure(frame, job.output, std::current_exception()));
                continue;
            }
            StageTimer t{reader_timings.read_wait_s};
            if (!to_composite.push(std::move(job))) break;
        }
        to_composite.close();
        finishThread();
    });
    for (int w = 0; w < workers; ++w)
        threads.emplace_back([&, w] {  // compositing worker
            while (auto job = to_composite.pop()) {
                try {
                    if (!request.io_only)
                        compositing.composite(*job, *compositors[std::size_t(w)], work_scenes[std::size_t(w)],
                                              thread_timings[std::size_t(w) + 2]);
                } catch (...) {
                    results.push(failure(job->frame, job->output, std::current_exception()));
                    continue;
                }
                if (!to_write.push(std::move(*job))) break;
            }
            if (--live_workers == 0) to_write.close();
            finishThread();
        });
    threads.emplace_back([&] {  // writer
        while (true) {
            std::optional<Job> job;
            {
                StageTimer t{writer_timings.write_idle_s};
                job = to_write.pop();
            }
            if (!job) break;
            try {
                StageTimer t{writer_timings.write_s};
                writeExrAtomic(job->files.front(), job->output);
                results.push(FrameResult{job->frame, FrameStatus::Written, job->output, "", std::nullopt});
            } catch (...) {
                results.push(failure(job->frame, job->output, std::current_exception()));
            }
        }
        finishThread();
    });

    std::optional<FrameResult> stopped_by;
    while (auto result = results.pop()) {
        if (cancelled) continue;  // frames finishing after a stop are not reported
        BatchProgress& p = report.progress;
        if (result->status == FrameStatus::Written) ++p.written;
        else if (result->status == FrameStatus::Skipped) ++p.skipped;
        else {
            ++p.failed;
            report.failures.push_back(*result);
        }
        p.elapsed_s = secondsSince(start);
        watch.frameFinished(*result, p);
        if (result->status == FrameStatus::Failed && !request.keep_going) {
            stopped_by = *result;
            cancelAll();
        }
    }
    for (std::thread& t : threads) t.join();
    report.progress.elapsed_s = secondsSince(start);
    report.warnings = compositing.warnings();
    for (const BatchTimings& t : thread_timings) {
        BatchTimings& sum = report.timings;
        sum.read_s += t.read_s, sum.map_extract_s += t.map_extract_s, sum.set_scene_s += t.set_scene_s;
        sum.composite_s += t.composite_s, sum.kernels_ms += t.kernels_ms, sum.store_s += t.store_s;
        sum.write_s += t.write_s, sum.read_wait_s += t.read_wait_s, sum.write_idle_s += t.write_idle_s;
    }
    watch.finished(report);
    if (stopped_by) {
        if (stopped_by->kind) throw Error(*stopped_by->kind, stopped_by->message);
        throw std::runtime_error(stopped_by->message);
    }
    return report;
}

}  // namespace decalcomp
