// Waiting for the device asleep (src/cl/asleep_wait.hpp): returns only once the event has
// completed, rethrows a failed event's error, and finishAsleep waits for work already enqueued.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>
#include <vector>

#include "cl/asleep_wait.hpp"
#include "support/random_scenes.hpp"

namespace decalcomp {
namespace {

TEST(AsleepWait, ReturnsOnlyOnceTheEventHasCompleted) {
    cl::UserEvent gate(test::cpuDevice().context());
    auto waiting = std::async(std::launch::async, [&] { waitAsleep(gate); });
    EXPECT_EQ(waiting.wait_for(std::chrono::milliseconds(200)), std::future_status::timeout);
    gate.setStatus(CL_COMPLETE);
    ASSERT_EQ(waiting.wait_for(std::chrono::seconds(20)), std::future_status::ready);
    waiting.get();
}

TEST(AsleepWait, AnEventThatCompletedBeforeTheWaitReturnsAtOnce) {
    cl::UserEvent gate(test::cpuDevice().context());
    gate.setStatus(CL_COMPLETE);
    auto waiting = std::async(std::launch::async, [&] { waitAsleep(gate); });
    ASSERT_EQ(waiting.wait_for(std::chrono::seconds(20)), std::future_status::ready);
}

TEST(AsleepWait, AFailedEventThrowsAsClWaitWould) {
    cl::UserEvent gate(test::cpuDevice().context());
    auto waiting = std::async(std::launch::async, [&] { waitAsleep(gate); });
    gate.setStatus(-1);
    ASSERT_EQ(waiting.wait_for(std::chrono::seconds(20)), std::future_status::ready);
    EXPECT_THROW(waiting.get(), cl::Error);
}

// The queue's commands wait on a user event: finishAsleep returns only after it fires and the
// copy behind it has landed.
TEST(AsleepWait, FinishWaitsForEverythingEnqueued) {
    ComputeDevice& device = test::cpuDevice();
    cl::CommandQueue queue(device.context(), device.info().device);
    cl::UserEvent gate(device.context());
    const std::vector<cl_int> values{1, 2, 3, 4};
    std::vector<cl_int> back(values.size(), 0);
    cl::Buffer buffer(device.context(), CL_MEM_READ_WRITE, values.size() * sizeof(cl_int));
    const std::vector<cl::Event> after{gate};
    queue.enqueueWriteBuffer(buffer, CL_FALSE, 0, values.size() * sizeof(cl_int), values.data(), &after);
    queue.enqueueReadBuffer(buffer, CL_FALSE, 0, back.size() * sizeof(cl_int), back.data());
    auto finishing = std::async(std::launch::async, [&] { finishAsleep(queue); });
    EXPECT_EQ(finishing.wait_for(std::chrono::milliseconds(200)), std::future_status::timeout);
    gate.setStatus(CL_COMPLETE);
    ASSERT_EQ(finishing.wait_for(std::chrono::seconds(20)), std::future_status::ready);
    finishing.get();
    EXPECT_EQ(back, values);
}

}  // namespace
}  // namespace decalcomp
