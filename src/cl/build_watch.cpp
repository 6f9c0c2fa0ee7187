#include "build_watch.hpp"

namespace decalcomp {

BuildWatch::BuildWatch(std::chrono::milliseconds after, std::function<void(const std::string&)> notice,
                       std::string message) {
    if (!notice) return;
    thread_ = std::thread([this, after, notice = std::move(notice), message = std::move(message)] {
        {
            std::unique_lock lock(mutex_);
            if (finished_.wait_for(lock, after, [this] { return done_; })) return;
        }
        // Outside the lock: the destructor waits for it, not the other way round. A notice that
        // throws says nothing; on this thread it would end the process.
        try {
            notice(message);
        } catch (...) {
        }
    });
}

BuildWatch::~BuildWatch() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        done_ = true;
    }
    finished_.notify_one();
    thread_.join();
}

}  // namespace decalcomp
