#include "io/exr_pool.hpp"

#include <OpenEXR/IlmThreadPool.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <ctime>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "decalcomp/exr_file.hpp"

namespace decalcomp::io {

namespace {

std::atomic<std::int64_t> g_cpu_ns[2];  // by PoolWork

std::int64_t threadCpuNs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return std::int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

// One runOnExrPool call. `next` is only advanced under the pool's mutex, so no index is handed
// out after the last; `work` is only called for a handed-out index, so never after the caller
// has returned.
struct PoolRun {
    PoolRun(const std::function<void(std::size_t)>& w, std::size_t n, PoolWork k) : work(w), count(n), kind(k) {}
    const std::function<void(std::size_t)>& work;
    const std::size_t count;
    const PoolWork kind;
    std::size_t next = 0;      // under the pool's mutex
    std::size_t finished = 0;  // likewise
    std::exception_ptr error;  // likewise

    void run(std::size_t index, std::exception_ptr& failure) {
        const std::int64_t start = threadCpuNs();
        try {
            work(index);
        } catch (...) {
            failure = std::current_exception();
        }
        g_cpu_ns[int(kind)] += threadCpuNs() - start;
    }
};

class CodecPool {
public:
    // Matches the thread count to OpenEXR's global pool (it may have changed since the last call).
    // The threads are detached: surplus ones end after their current index.
    void follow(int threads) {
        const std::lock_guard lock(mutex_);
        if (threads < threads_) {
            retire_ += threads_ - threads;
            work_or_retire_.notify_all();
        }
        for (; threads_ < threads; ++threads_) std::thread([this] { serve(); }).detach();
        threads_ = threads;
    }

    void run(PoolWork kind, std::size_t count, const std::function<void(std::size_t)>& work) {
        auto call = std::make_shared<PoolRun>(work, count, kind);
        std::unique_lock lock(mutex_);
        if (threads_ > 0 && count > 1) {
            calls_.push_back(call);
            work_or_retire_.notify_all();
        }
        while (call->next < call->count) runNextIndex(lock, *call);  // the caller's share
        all_finished_.wait(lock, [&] { return call->finished == call->count; });
        std::erase(calls_, call);
        if (call->error) std::rethrow_exception(call->error);
    }

private:
    std::mutex mutex_;
    std::condition_variable work_or_retire_, all_finished_;
    std::vector<std::shared_ptr<PoolRun>> calls_;  // in arrival order
    int threads_ = 0;                              // serving, less those asked to retire
    int retire_ = 0;                               // threads asked to end

    // Hands out the call's next index and runs it outside the lock (held on entry and return).
    void runNextIndex(std::unique_lock<std::mutex>& lock, PoolRun& call) {
        const std::size_t index = call.next++;
        lock.unlock();
        std::exception_ptr failure;
        call.run(index, failure);
        lock.lock();
        if (failure && !call.error) call.error = failure;
        if (++call.finished == call.count) all_finished_.notify_all();
    }

    // The oldest decode call with an index left, else the oldest encode call; null when none.
    std::shared_ptr<PoolRun> nextCall() const {
        std::shared_ptr<PoolRun> chosen;
        for (const auto& call : calls_) {
            if (call->next >= call->count) continue;
            if (call->kind == PoolWork::Decode) return call;
            if (!chosen) chosen = call;
        }
        return chosen;
    }

    void serve() {
        std::unique_lock lock(mutex_);
        for (;;) {
            std::shared_ptr<PoolRun> call;
            work_or_retire_.wait(lock, [&] { return retire_ > 0 || (call = nextCall()); });
            if (!call) {
                retire_ -= 1;
                return;
            }
            runNextIndex(lock, *call);
        }
    }
};

// Lives as long as the process: its threads may still wait on it while static objects go.
CodecPool& codecPool() {
    static auto* pool = new CodecPool;
    return *pool;
}

}  // namespace

void runOnExrPool(PoolWork kind, std::size_t count, const std::function<void(std::size_t)>& work) {
    if (count == 0) return;
    CodecPool& pool = codecPool();
    pool.follow(std::max(0, IlmThread::ThreadPool::globalThreadPool().numThreads()));
    pool.run(kind, count, work);
}

}  // namespace decalcomp::io

namespace decalcomp {

CodecCpu codecCpuSeconds() {
    return {1e-9 * double(io::g_cpu_ns[int(io::PoolWork::Decode)].load()),
            1e-9 * double(io::g_cpu_ns[int(io::PoolWork::Encode)].load())};
}

}  // namespace decalcomp
