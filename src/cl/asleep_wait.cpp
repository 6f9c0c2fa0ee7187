#include "cl/asleep_wait.hpp"

#include <condition_variable>
#include <memory>
#include <mutex>

namespace decalcomp {

namespace {

struct Completion {
    std::mutex mutex;
    std::condition_variable changed;
    bool done = false;
};

// The runtime calls this from its own thread once the event is complete (or failed); it owns one
// reference to the completion, so the waiter may have gone by then.
void CL_CALLBACK completed(cl_event, cl_int, void* data) {
    std::unique_ptr<std::shared_ptr<Completion>> owned(static_cast<std::shared_ptr<Completion>*>(data));
    Completion& completion = **owned;
    {
        const std::lock_guard lock(completion.mutex);
        completion.done = true;
    }
    completion.changed.notify_all();
}

}  // namespace

void waitAsleep(const cl::Event& event) {
    auto completion = std::make_shared<Completion>();
    auto* reference = new std::shared_ptr<Completion>(completion);
    if (clSetEventCallback(event(), CL_COMPLETE, completed, reference) != CL_SUCCESS) {
        delete reference;  // no callback will come: wait the runtime's way
        event.wait();
        return;
    }
    {
        std::unique_lock lock(completion->mutex);
        completion->changed.wait(lock, [&] { return completion->done; });
    }
    event.wait();  // complete by now: returns at once, or throws the failure
}

void finishAsleep(cl::CommandQueue& queue) {
    cl::Event marker;
    queue.enqueueMarkerWithWaitList(nullptr, &marker);
    queue.flush();
    waitAsleep(marker);
}

}  // namespace decalcomp
