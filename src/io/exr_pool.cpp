#include "io/exr_pool.hpp"

#include <OpenEXR/IlmThreadPool.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <ctime>
#include <exception>
#include <memory>
#include <mutex>

#include "decalcomp/exr_file.hpp"

namespace decalcomp::io {

namespace {

std::atomic<std::int64_t> g_cpu_ns[2];  // PoolWork::Decode, PoolWork::Encode

std::int64_t threadCpuNs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return std::int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

// What the caller and its pool tasks share. A task may start after the caller has returned (it
// waited in the pool's queue): it then finds no index left and never touches `work`.
struct PoolRun {
    PoolRun(const std::function<void(std::size_t)>& w, std::size_t n, PoolWork k) : work(w), count(n), kind(k) {}
    const std::function<void(std::size_t)>& work;
    const std::size_t count;
    const PoolWork kind;
    std::atomic<std::size_t> next{0};
    std::size_t finished = 0;  // under mutex
    std::exception_ptr error;  // likewise
    std::mutex mutex;
    std::condition_variable all_finished;

    // Runs indices until none is left.
    void drain() {
        std::size_t ran = 0;
        const std::int64_t start = threadCpuNs();
        std::exception_ptr failure;
        for (std::size_t i = next++; i < count; i = next++, ++ran) {
            try {
                work(i);
            } catch (...) {
                if (!failure) failure = std::current_exception();
            }
        }
        if (ran == 0) return;
        g_cpu_ns[int(kind)] += threadCpuNs() - start;
        const std::lock_guard lock(mutex);
        if (failure && !error) error = failure;
        finished += ran;
        if (finished == count) all_finished.notify_all();
    }
};

class DrainTask : public IlmThread::Task {
public:
    DrainTask(IlmThread::TaskGroup* group, std::shared_ptr<PoolRun> run) : Task(group), run_(std::move(run)) {}
    void execute() override { run_->drain(); }

private:
    std::shared_ptr<PoolRun> run_;
};

// Tasks belong to a group, whose destructor waits for them; the callers wait for their indices
// instead, so the tasks' group lives as long as the process.
IlmThread::TaskGroup& detachedTasks() {
    static auto* group = new IlmThread::TaskGroup;
    return *group;
}

}  // namespace

void runOnExrPool(PoolWork kind, std::size_t count, const std::function<void(std::size_t)>& work) {
    if (count == 0) return;
    auto run = std::make_shared<PoolRun>(work, count, kind);
    IlmThread::ThreadPool& pool = IlmThread::ThreadPool::globalThreadPool();
    const std::size_t helpers = std::min<std::size_t>(count - 1, std::size_t(std::max(0, pool.numThreads())));
    for (std::size_t t = 0; t < helpers; ++t) pool.addTask(new DrainTask(&detachedTasks(), run));
    run->drain();
    std::unique_lock lock(run->mutex);
    run->all_finished.wait(lock, [&] { return run->finished == run->count; });
    if (run->error) std::rethrow_exception(run->error);
}

}  // namespace decalcomp::io

namespace decalcomp {

CodecCpu codecCpuSeconds() {
    return {1e-9 * double(io::g_cpu_ns[int(io::PoolWork::Decode)].load()),
            1e-9 * double(io::g_cpu_ns[int(io::PoolWork::Encode)].load())};
}

}  // namespace decalcomp
