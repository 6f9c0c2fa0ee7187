#pragma once
// A notice while a kernel build runs long (ComputeDevice::setSlowBuildNotice): a cold build on
// some drivers takes minutes, and a run that says nothing meanwhile looks hung.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace decalcomp {

// Calls `notice` with `message` from a thread of its own when the watch is still alive `after`
// its construction; never when it is destroyed before. Destroying it does not wait for `after`.
// An exception from `notice` is swallowed: a note must not end the process.
class BuildWatch {
public:
    BuildWatch(std::chrono::milliseconds after, std::function<void(const std::string&)> notice, std::string message);
    ~BuildWatch();
    BuildWatch(const BuildWatch&) = delete;
    BuildWatch& operator=(const BuildWatch&) = delete;

private:
    std::mutex mutex_;
    std::condition_variable finished_;
    bool done_ = false;
    std::thread thread_;
};

}  // namespace decalcomp
