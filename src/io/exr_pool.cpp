#include "io/exr_pool.hpp"

#include <OpenEXR/IlmThreadPool.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "core/thread_cpu_time.hpp"
#include "decalcomp/exr_file.hpp"

namespace decalcomp::io {

namespace {

std::atomic<std::int64_t> g_cpu_ns[2];  // by PoolWork

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
    ~CodecPool() { follow(0); }  // joined, so their thread_local buffers and compressors are freed

    // Matches the thread count to OpenEXR's global pool (it may have changed since the last call).
    // Surplus threads end after their current chunk and are joined before this returns.
    void follow(int count) {
        const std::lock_guard resizing(resize_mutex_);
        std::vector<std::thread> leaving;
        {
            const std::lock_guard lock(mutex_);
            if (int(threads_.size()) == count) return;
            wanted_ = count;
            while (int(threads_.size()) > count) {
                leaving.push_back(std::move(threads_.back()));
                threads_.pop_back();
            }
            while (int(threads_.size()) < count) {
                const int slot = int(threads_.size());
                threads_.emplace_back([this, slot] { serve(slot); });
            }
        }
        work_or_leave_.notify_all();
        for (std::thread& thread : leaving) thread.join();
    }

    void run(PoolWork kind, std::size_t count, const std::function<void(std::size_t)>& work) {
        auto call = std::make_shared<PoolRun>(work, count, kind);
        std::unique_lock lock(mutex_);
        if (!threads_.empty() && count > 1) {
            calls_.push_back(call);
            work_or_leave_.notify_all();
        }
        while (call->next < call->count) runNextIndex(lock, *call);  // the caller's share
        all_finished_.wait(lock, [&] { return call->finished == call->count; });
        std::erase(calls_, call);
        if (call->error) std::rethrow_exception(call->error);
    }

private:
    std::mutex resize_mutex_;  // one follow() at a time: it joins outside mutex_
    std::mutex mutex_;
    std::condition_variable work_or_leave_, all_finished_;
    std::vector<std::shared_ptr<PoolRun>> calls_;  // in arrival order
    std::vector<std::thread> threads_;             // slot i serves while i < wanted_
    int wanted_ = 0;

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

    void serve(int slot) {
        std::unique_lock lock(mutex_);
        for (;;) {
            std::shared_ptr<PoolRun> call;
            work_or_leave_.wait(lock, [&] { return slot >= wanted_ || (call = nextCall()); });
            if (!call) return;  // (slot >= wanted_ is tested first)
            runNextIndex(lock, *call);
        }
    }
};

CodecPool& codecPool() {
    static CodecPool pool;
    return pool;
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
