#pragma once
// Waiting for the device without spinning a core. NVIDIA's OpenCL busy-waits in clWaitForEvents and
// clFinish; a batch's workers wait on the device while OpenEXR's pool needs every core for the
// codecs, so they sleep on a completion callback instead.
#include <CL/opencl.hpp>

namespace decalcomp {

// Returns once `event` has completed; throws cl::Error as cl::Event::wait would if it failed.
void waitAsleep(const cl::Event& event);
// Returns once every command enqueued on `queue` so far has completed (clFinish, asleep).
void finishAsleep(cl::CommandQueue& queue);

}  // namespace decalcomp
