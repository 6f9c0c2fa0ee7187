#pragma once
// OpenCL device selection and the built decalcomp program.
#include <CL/opencl.hpp>

#include <chrono>
#include <functional>
#include <map>
#include <mutex>
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

// The paths of a filtered or texture-space frame's shading kernel (kernels/shading.cl).
struct ShadingPaths {
    bool taps = false;  // the pixel filter by taps
    bool fast = false;  // the pixel filter in closed form (`:fast`); its mixed pixels take taps too
    bool rest = false;  // texture-space decals, at their rest pose
    bool any() const { return taps || fast || rest; }
    // A program's key: the variant's two bits (DC_VARIANT_ALBEDO_ONLY, DC_VARIANT_FLAT), the paths above
    int key(int variant) const { return variant | (taps ? 4 : 0) | (fast ? 8 : 0) | (rest ? 16 : 0); }
};

// A context and in-order profiling queue on one device, with the embedded programs built once.
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
    // Programs, each built on first use; both throw Error(Device) with the device name, options and
    // full build log. Safe to call from several threads.
    // Every kernel but the shading kernels of filtered and texture-space frames: binning, the
    // point-sampled shading, the rest pose's lookups, the bake.
    cl::Program& program();
    // The kernel `dc_shade` of filtered and texture-space frames, of one variant (DC_VARIANT_ALBEDO_ONLY
    // and DC_VARIANT_FLAT bits) with the given paths alone. Each path inlines a whole decal
    // evaluation, and NVIDIA's compiler took over 8 minutes over every path and variant in one
    // program; a frame needs one variant and two or three paths.
    cl::Program& shadingProgram(int variant, const ShadingPaths& paths);

    // Calls `notice` (from a thread of its own, while the build goes on) when a program's build is
    // still running `after` it began, with a line naming the device and the program: a cold build
    // on NVIDIA's driver has taken minutes, and a run that says nothing meanwhile looks hung. Set
    // it before the first composite; an empty notice says nothing.
    using BuildNotice = std::function<void(const std::string& message)>;
    void setSlowBuildNotice(std::chrono::milliseconds after, BuildNotice notice);

private:
    cl::Program build(const std::string& options, const std::string& what);

    DeviceInfo info_;
    cl::Context context_;
    cl::CommandQueue queue_;
    // Compositors on worker threads share the device: each program builds once, and a thread waits
    // only for the program it asks for (the map's lock is not held over a build).
    struct LazyProgram {
        std::mutex building;
        cl::Program program;  // null until built
    };
    cl::Program& buildOnce(LazyProgram& lazy, const std::string& options, const std::string& what);

    std::mutex programs_mutex_;  // over the map
    LazyProgram point_program_;
    std::map<int, LazyProgram> shading_programs_;  // by variant and paths
    bool profiling_ = true;
    std::chrono::milliseconds slow_build_after_{0};
    BuildNotice slow_build_notice_;
};

// How long the command line, batches and the Python module let a kernel build run before they say
// that it is building: $DECALCOMP_BUILD_NOTICE_AFTER seconds (0: at every build), default 10.
// Throws Error(Usage) for a value that is not a number of seconds.
std::chrono::milliseconds slowBuildNoticeAfter();

// The program source handed to the OpenCL compiler: every kernels/*.cl with its includes resolved
// (each header once, `#line` markers naming kernels/ files), assembled at build time.
// DECALCOMP_KERNEL_DIR in the environment makes it read and assemble that directory instead
// (iteration); a missing include then throws Error(Device) naming file and line.
std::string programSource();
// Options used for every build on a device of this type (DeviceInfo::type): CPU devices get
// -DDC_CPU_DEVICE, the kernels' code shaped for scalar work-items (kernels/shared_types.h).
// $DECALCOMP_KERNEL_FLAVOUR=gpu or cpu builds any device one way (the GPUs' code tested on PoCL);
// another value throws Error(Usage).
std::string buildOptions(const std::string& device_type);
// The programs ComputeDevice builds, for their register caps.
enum class ProgramKind {
    Point,    // binning and point-sampled shading (ComputeDevice::program)
    Shading,  // the shading of filtered and texture-space frames (ComputeDevice::shadingProgram)
};
// The register cap a program builds with on a device offering these extensions: on NVIDIA
// (cl_nv_compiler_options) " -cl-nv-maxrregcount=64" for the point program and 128 for the shading
// programs (docs/decisions.md), or DECALCOMP_POINT_REGISTERS / DECALCOMP_SHADING_REGISTERS where
// set (0: none); "" elsewhere.
std::string registerCap(const std::string& device_extensions, ProgramKind program);

}  // namespace decalcomp
