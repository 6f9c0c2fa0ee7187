#include "io/exr_pool.hpp"

#include <OpenEXR/IlmThreadPool.h>

#include <exception>
#include <mutex>

namespace decalcomp::io {

namespace {

// What the calls share: the work, and the first failure.
struct PoolRun {
    const std::function<void(std::size_t)>& work;
    std::exception_ptr error;
    std::mutex error_mutex;
};

class PoolTask : public IlmThread::Task {
public:
    PoolTask(IlmThread::TaskGroup* group, PoolRun& run, std::size_t index) : Task(group), run_(run), index_(index) {}
    void execute() override {
        try {
            run_.work(index_);
        } catch (...) {  // rethrown by runOnExrPool once the group is done
            const std::lock_guard lock(run_.error_mutex);
            if (!run_.error) run_.error = std::current_exception();
        }
    }

private:
    PoolRun& run_;
    std::size_t index_;
};

}  // namespace

void runOnExrPool(std::size_t count, const std::function<void(std::size_t)>& work) {
    PoolRun run{work, nullptr, {}};
    {
        IlmThread::TaskGroup group;  // waits for its tasks when it goes out of scope
        for (std::size_t i = 0; i < count; ++i) IlmThread::ThreadPool::addGlobalTask(new PoolTask(&group, run, i));
    }
    if (run.error) std::rethrow_exception(run.error);
}

}  // namespace decalcomp::io
