#pragma once
// OpenCL device selection and the built decalcomp program.
#include <CL/opencl.hpp>

#include <string>
#include <vector>

namespace decalcomp {

struct DeviceInfo {
    int index = 0;  // position in listDevices(), stable for a given machine
    std::string name, vendor, platform, version, type;  // type: "gpu", "cpu", "accelerator", "other"
    cl::Device device;
    cl::Platform platform_handle;
};

// Every device of every platform, in platform then device order. Empty when no ICD is installed.
std::vector<DeviceInfo> listDevices();

// Picks a device: "" = first GPU, else first CPU, else the first device; a number = that index;
// "gpu"/"cpu"/"accelerator" = first of that type; any other text = first whose name, vendor or
// platform contains it (case-insensitive). Throws Error(Device) listing the devices on no match.
DeviceInfo selectDevice(const std::string& selector);

// Several devices: "all" (every GPU, else every device), or selectDevice() selectors separated by
// ',' ("0,1", "gpu,cpu"); naming one device twice gives two instances of it (two contexts).
std::vector<DeviceInfo> selectDevices(const std::string& spec);

// Names an OpenCL status code ("CL_INVALID_VALUE"), or "CL error N" for unknown codes.
std::string clErrorName(int code);

// A context and in-order profiling queue on one device, with the embedded program built once.
class ComputeDevice {
public:
    explicit ComputeDevice(const std::string& selector = "");
    explicit ComputeDevice(DeviceInfo device);
    // Embeds the compositor in a host application that owns OpenCL: its context, device and
    // in-order queue. Kernel times (CompositeStats) are 0 unless the queue has profiling enabled.
    ComputeDevice(const cl::Context& context, const cl::Device& device, const cl::CommandQueue& queue);
    bool profiling() const { return profiling_; }
    const DeviceInfo& info() const { return info_; }
    cl::Context& context() { return context_; }
    cl::CommandQueue& queue() { return queue_; }
    // The kernels, built on first use. Without `full_shading`, every kernel but the shading kernels
    // of filtered and texture-space frames, whose inlined filter paths are most of a cold build
    // (over 9 minutes on NVIDIA's compiler), so that point-sampled work never waits for them; with
    // it, or once that program exists, every kernel. Throws Error(Device) with the device name,
    // options and full build log.
    cl::Program& program(bool full_shading = false);

private:
    cl::Program build(const std::string& options);

    DeviceInfo info_;
    cl::Context context_;
    cl::CommandQueue queue_;
    cl::Program program_, full_program_;  // null until built
    bool profiling_ = true;
};

// The program source handed to the OpenCL compiler: every kernels/*.cl with its includes resolved
// (each header once, `#line` markers naming kernels/ files), assembled at build time.
// DECALCOMP_KERNEL_DIR in the environment makes it read and assemble that directory instead
// (iteration); a missing include then throws Error(Device) naming file and line.
std::string programSource();
// Options used for every build.
std::string buildOptions();

}  // namespace decalcomp
