// The batch loop over Frame: one reader thread, compositing workers (per device) and one writer
// thread joined by bounded queues, with OpenEXR's thread pool decoding and encoding inside each
// read and write.
#include <OpenEXR/ImfThreading.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

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
#include "decalcomp/frame.hpp"
#include "decalcomp/frame_cameras.hpp"
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
    std::string output;  // for reports: the output pattern's path (or folder)
    std::unique_ptr<Frame> work;
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

// A pattern's path for the frame; a path without a frame token names the same file every frame.
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

std::vector<std::string> frameInputs(const BatchRequest& request, const BatchPlan& plan, int frame) {
    FrameSources sources = frameSources(request, plan, frame);
    for (const auto& [attribute, path] : sources.pass_files) sources.inputs.push_back(path);
    return sources.inputs;
}

// The files a frame's outputs may be: the pattern's path, or for a folder each of its input
// files' names there (which of them change is known only once the frame's channels are mapped).
std::vector<fs::path> candidateOutputs(const BatchRequest& request, const BatchPlan& plan, int frame) {
    if (!plan.outputIsFolder()) return {fs::path(plan.outputAt(frame))};
    const fs::path folder(plan.outputAt(frame));
    std::vector<fs::path> paths;
    for (const std::string& input : frameInputs(request, plan, frame))
        paths.push_back(folder / fs::path(input).filename());
    return paths;
}

// A frame is done when an output exists: the outputs of a frame are renamed into place together,
// after all of them are complete.
bool frameDone(const BatchRequest& request, const BatchPlan& plan, int frame) {
    std::error_code ec;
    for (const fs::path& path : candidateOutputs(request, plan, frame))
        if (fs::is_regular_file(path, ec)) return true;
    return false;
}

// writeExrTemporary writes ".NAME.tmp-PID" beside NAME (src/io/exr_file.cpp). A run killed while
// writing leaves one behind; the next run removes those of its own frames (never another shard's).
void removeStaleTemporaries(const BatchRequest& request, const BatchPlan& plan) {
    std::map<fs::path, std::set<std::string>> names;  // folder -> output file names
    for (int frame : plan.frames)
        for (const fs::path& out : candidateOutputs(request, plan, frame))
            names[out.parent_path()].insert(out.filename().string());
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

void createOutputFolders(const BatchRequest& request, const BatchPlan& plan) {
    std::set<fs::path> folders;
    for (int frame : plan.frames)
        for (const fs::path& out : candidateOutputs(request, plan, frame)) folders.insert(out.parent_path());
    if (!request.preview.empty())
        for (int frame : plan.frames) folders.insert(fs::path(pathAt(request.preview, frame)).parent_path());
    for (const fs::path& folder : folders) {
        if (folder.empty()) continue;
        std::error_code ec;
        fs::create_directories(folder, ec);
        if (ec) throw outputError(fmt::format("{}: cannot create the output folder: {}", folder.string(), ec.message()));
    }
}

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

}  // namespace

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

    // ---- set-up, once per batch ----
    const FrameCameras cameras(request.camera, request.cameras);
    report.camera_source = cameras.describe();
    DecalScene scene;
    std::vector<DeviceWorkers> devices;
    const int workers_per_device = std::max(1, request.composite_workers);
    if (!request.io_only) {
        scene = loadScene(request.scene);
        if (!plan.frames.empty())
            for (DeviceInfo& info : selectDevices(request.device)) {
                DeviceWorkers& d = devices.emplace_back();
                d.device = std::make_unique<ComputeDevice>(std::move(info));
                report.devices.push_back(d.device->info().name);
                for (int w = 0; w < workers_per_device; ++w) {
                    d.compositors.push_back(std::make_unique<Compositor>(*d.device));
                    d.compositors.back()->setScene(scene);
                }
            }
    }
    const int workers = request.io_only ? 1 : int(devices.size()) * workers_per_device;
    // After the scene: decoding its EXR textures through OpenImageIO may change the global count.
    Imf::setGlobalThreadCount(request.exr_threads > 0 ? request.exr_threads
                                                      : int(std::max(1u, std::thread::hardware_concurrency())));
    createOutputFolders(request, plan);
    removeStaleTemporaries(request, plan);
    SequenceConventions sequence;  // depth and normal readings settled once for the sequence
    WarningSet warnings;
    FrameOptions options;
    options.mapping = request.mapping;
    options.compositing.binned = request.binned;
    options.label = request.input;  // warnings name the sequence, so each is reported once

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
            job.output = plan.outputAt(frame);
            if (request.resume && frameDone(request, plan, frame)) {
                results.push(FrameResult{frame, FrameStatus::Skipped, job.output, "", std::nullopt});
                continue;
            }
            try {
                FrameSources sources = frameSources(request, plan, frame);
                sources.camera = cameras.explicitCamera(frame);
                FrameTargets targets{job.output, request.preview.empty() ? "" : pathAt(request.preview, frame),
                                     request.overwrite_input};
                FrameOptions frame_options = options;
                frame_options.frame_number = double(frame);
                job.work = std::make_unique<Frame>(std::move(sources), std::move(targets), std::move(frame_options));
                StageTimer t{reader_timings.read_s};
                job.work->read();
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
            BatchTimings& timings = thread_timings[std::size_t(w) + 2];
            Compositor* compositor =
                request.io_only ? nullptr
                                : devices[std::size_t(w / workers_per_device)]
                                      .compositors[std::size_t(w % workers_per_device)]
                                      .get();
            while (auto job = to_composite.pop()) {
                try {
                    {
                        StageTimer t{timings.prepare_s};
                        job->work->prepare(scene, &sequence);  // empty for --io-only: nothing to composite
                    }
                    warnings.add(job->frame, job->work->report().warnings);
                    if (compositor) {
                        StageTimer t{timings.composite_s};
                        job->work->composite(*compositor);
                        timings.kernels_ms += job->work->report().stats.totalKernelMs();
                    }
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
                const std::vector<std::string>& written = job->work->writeBack();
                const std::string output = written.size() == 1 ? written.front() : job->output;
                job->work.reset();  // the frame's planes go before the next one is taken
                results.push(FrameResult{job->frame, FrameStatus::Written, output, "", std::nullopt});
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
    report.warnings = warnings.list();
    for (const BatchTimings& t : thread_timings) {
        BatchTimings& sum = report.timings;
        sum.read_s += t.read_s, sum.prepare_s += t.prepare_s, sum.composite_s += t.composite_s;
        sum.kernels_ms += t.kernels_ms, sum.write_s += t.write_s;
        sum.read_wait_s += t.read_wait_s, sum.write_idle_s += t.write_idle_s;
    }
    watch.finished(report);
    if (stopped_by) {
        if (stopped_by->kind) throw Error(*stopped_by->kind, stopped_by->message);
        throw std::runtime_error(stopped_by->message);
    }
    return report;
}

}  // namespace decalcomp
