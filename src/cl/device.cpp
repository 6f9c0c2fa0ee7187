#include "decalcomp/device.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>

#include "build_watch.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

std::string typeName(cl_device_type type) {
    if (type & CL_DEVICE_TYPE_GPU) return "gpu";
    if (type & CL_DEVICE_TYPE_CPU) return "cpu";
    if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

std::string describe(const std::vector<DeviceInfo>& devices) {
    std::string list;
    for (const auto& d : devices) list += fmt::format("{}{}: {} ({}, {})", list.empty() ? "" : "; ", d.index, d.name, d.type, d.platform);
    return list.empty() ? "none" : list;
}

DeviceInfo describeDevice(const cl::Device& device, const cl::Platform& platform, int index) {
    DeviceInfo info;
    info.index = index;
    info.name = device.getInfo<CL_DEVICE_NAME>();
    info.vendor = device.getInfo<CL_DEVICE_VENDOR>();
    info.version = device.getInfo<CL_DEVICE_VERSION>();
    info.type = typeName(device.getInfo<CL_DEVICE_TYPE>());
    info.platform = platform.getInfo<CL_PLATFORM_NAME>();
    info.device = device;
    info.platform_handle = platform;
    return info;
}

}  // namespace

std::vector<DeviceInfo> listDevices() {
    std::vector<DeviceInfo> devices;
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error&) {
        return devices;  // no ICD, or the loader found no platform
    }
    for (auto& platform : platforms) {
        std::vector<cl::Device> platform_devices;
        try {
            platform.getDevices(CL_DEVICE_TYPE_ALL, &platform_devices);
        } catch (const cl::Error&) {
            continue;
        }
        for (auto& device : platform_devices) devices.push_back(describeDevice(device, platform, int(devices.size())));
    }
    return devices;
}

DeviceInfo selectDevice(const std::string& selector) {
    const auto devices = listDevices();
    if (devices.empty())
        throw deviceError("no OpenCL device found (install pocl-opencl-icd for the CPU, or a GPU driver)");
    auto first_of_type = [&](const std::string& type) -> const DeviceInfo* {
        for (const auto& d : devices)
            if (d.type == type) return &d;
        return nullptr;
    };
    if (selector.empty()) {
        if (auto* gpu = first_of_type("gpu")) return *gpu;
        if (auto* cpu = first_of_type("cpu")) return *cpu;
        return devices.front();
    }
    if (std::all_of(selector.begin(), selector.end(), [](unsigned char c) { return std::isdigit(c); })) {
        const std::size_t index = std::stoul(selector);
        if (index < devices.size()) return devices[index];
        throw deviceError(fmt::format("--device {}: no device with that index (devices: {})", selector, describe(devices)));
    }
    const std::string wanted = lower(selector);
    if (wanted == "gpu" || wanted == "cpu" || wanted == "accelerator") {
        if (auto* d = first_of_type(wanted)) return *d;
        throw deviceError(fmt::format("--device {}: no {} device (devices: {})", selector, wanted, describe(devices)));
    }
    for (const auto& d : devices)
        if (lower(d.name).find(wanted) != std::string::npos || lower(d.vendor).find(wanted) != std::string::npos ||
            lower(d.platform).find(wanted) != std::string::npos)
            return d;
    throw deviceError(fmt::format("--device {}: no device matches (devices: {})", selector, describe(devices)));
}

std::vector<DeviceInfo> selectDevices(const std::string& spec) {
    std::vector<DeviceInfo> chosen;
    if (lower(spec) == "all") {
        const auto devices = listDevices();
        for (const auto& d : devices)
            if (d.type == "gpu") chosen.push_back(d);
        if (chosen.empty()) chosen = devices;
        if (chosen.empty()) return {selectDevice("")};  // throws: no device
        return chosen;
    }
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = spec.find(',', start);
        const std::string one = spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (one.empty() && spec.find(',') != std::string::npos)
            throw Error(ErrorKind::Usage, fmt::format("--device {}: empty device in the list", spec));
        chosen.push_back(selectDevice(one));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return chosen;
}

ComputeDevice::ComputeDevice(const std::string& selector) : ComputeDevice(selectDevice(selector)) {}

ComputeDevice::ComputeDevice(const cl::Context& context, const cl::Device& device, const cl::CommandQueue& queue)
    : context_(context), queue_(queue) {
    try {
        const cl::Platform platform(device.getInfo<CL_DEVICE_PLATFORM>());
        info_ = describeDevice(device, platform, -1);
        for (const DeviceInfo& listed : listDevices())
            if (listed.device() == device()) info_.index = listed.index;
        const cl_command_queue_properties properties = queue.getInfo<CL_QUEUE_PROPERTIES>();
        profiling_ = (properties & CL_QUEUE_PROFILING_ENABLE) != 0;
        if (properties & CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE)
            throw Error(ErrorKind::Usage, fmt::format("{}: the compositor needs an in-order queue", info_.name));
    } catch (const cl::Error& e) {
        throw deviceError(fmt::format("embedding an OpenCL context: {} failed: {}", e.what(), clErrorName(e.err())));
    }
}

ComputeDevice::ComputeDevice(DeviceInfo info) : info_(std::move(info)) {
    try {
        context_ = cl::Context(info_.device);
        queue_ = cl::CommandQueue(context_, info_.device, CL_QUEUE_PROFILING_ENABLE);
    } catch (const cl::Error& e) {
        throw deviceError(fmt::format("{}: {} failed: {}", info_.name, e.what(), clErrorName(e.err())));
    }
}

cl::Program& ComputeDevice::buildOnce(LazyProgram& lazy, const std::string& options, const std::string& what) {
    std::lock_guard lock(lazy.building);
    if (!lazy.program()) lazy.program = build(options, what);  // one that throws is tried again next time
    return lazy.program;
}

std::chrono::milliseconds slowBuildNoticeAfter() {
    constexpr const char* kVariable = "DECALCOMP_BUILD_NOTICE_AFTER";
    const char* setting = std::getenv(kVariable);
    if (!setting || !*setting) return std::chrono::seconds(10);
    char* end = nullptr;
    const double seconds = std::strtod(setting, &end);
    if (*end != '\0' || !(seconds >= 0.0) || seconds > 1e9)
        throw Error(ErrorKind::Usage, fmt::format("{}={}: not a number of seconds; e.g. {}=30, or 0 to say it at "
                                                  "every kernel build",
                                                  kVariable, setting, kVariable));
    return std::chrono::milliseconds(std::llround(seconds * 1000.0));
}

void ComputeDevice::setSlowBuildNotice(std::chrono::milliseconds after, BuildNotice notice) {
    slow_build_after_ = after;
    slow_build_notice_ = std::move(notice);
}

cl::Program& ComputeDevice::program() {
    return buildOnce(point_program_,
                     buildOptions(info_.type) +
                         registerCap(info_.device.getInfo<CL_DEVICE_EXTENSIONS>(), ProgramKind::Point) +
                         " -DDC_POINT_SHADING_ONLY",  // (kernels/shading.cl)
                     "binning and point-sampled shading");
}

cl::Program& ComputeDevice::shadingProgram(int variant, const ShadingPaths& paths) {
    if (variant < 0 || variant > 3)
        throw Error(ErrorKind::Usage,
                    fmt::format("shading program: variant {} is not an albedo-only and flat combination", variant));
    LazyProgram* lazy = nullptr;
    {
        std::lock_guard lock(programs_mutex_);
        lazy = &shading_programs_[paths.key(variant)];  // std::map: the entry stays where it is as others are added
    }
    std::string what;
    if (paths.taps) what = "the pixel filter's taps";
    if (paths.fast) what += fmt::format("{}the pixel filter in closed form", what.empty() ? "" : ", ");
    if (paths.rest) what += fmt::format("{}texture-space decals", what.empty() ? "" : ", ");
    return buildOnce(*lazy,
                     fmt::format("{}{} -DDC_SHADING_PROGRAM -DDC_SHADE_VARIANT={} -DDC_PATH_TAPS={:d} "
                                 "-DDC_PATH_FAST={:d} -DDC_PATH_REST={:d}",
                                 buildOptions(info_.type),
                                 registerCap(info_.device.getInfo<CL_DEVICE_EXTENSIONS>(), ProgramKind::Shading),
                                 variant, paths.taps, paths.fast, paths.rest),
                     "shading with " + (what.empty() ? std::string("no path") : what));
}

namespace {

// The device's binary of a built program (PTX on NVIDIA: where registers spill, which loads
// go to local memory), as DIR/program-<hash of the options>.bin, for kernel work.
void writeProgramBinary(const cl::Program& program, const std::string& dir, const std::string& options) {
    const auto binaries = program.getInfo<CL_PROGRAM_BINARIES>();
    if (binaries.empty()) return;
    const std::string path = fmt::format("{}/program-{:016x}.bin", dir, std::hash<std::string>{}(options));
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(binaries.front().data()), std::streamsize(binaries.front().size()));
    if (!out) {  // a missing folder: say so rather than name a file that is not there
        std::cerr << "program binary (options '" << options << "'): cannot write " << path << "\n";
        return;
    }
    std::cerr << "program binary (options '" << options << "'): " << path << "\n";
}

}  // namespace

cl::Program ComputeDevice::build(const std::string& options, const std::string& what) {
    const BuildWatch watch(slow_build_after_, slow_build_notice_,
                           fmt::format("{}: still compiling the OpenCL kernels for {} after {:g} s; drivers "
                                       "usually keep what they build, so later runs skip this",
                                       info_.name, what, std::chrono::duration<double>(slow_build_after_).count()));
    cl::Program program;
    try {
        program = cl::Program(context_, programSource());
        program.build({info_.device}, options.c_str());
        if (std::getenv("DECALCOMP_CL_BUILD_LOG"))  // the compiler's notes even on success
            std::cerr << program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(info_.device) << "\n";
        if (const char* dir = std::getenv("DECALCOMP_CL_BINARY_DIR")) writeProgramBinary(program, dir, options);
    } catch (const cl::BuildError& e) {
        std::string log;
        for (const auto& [device, text] : e.getBuildLog()) log += text;
        throw deviceError(fmt::format("{}: kernel build failed with options '{}':\n{}", info_.name, options, log));
    } catch (const cl::Error& e) {
        std::string log;
        try {
            log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(info_.device);
        } catch (const cl::Error&) {
        }
        throw deviceError(fmt::format("{}: kernel build failed ({}) with options '{}':\n{}", info_.name,
                                      clErrorName(e.err()), options, log));
    }
    return program;
}

}  // namespace decalcomp
