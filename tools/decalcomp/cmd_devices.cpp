#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp::cli {

Command addDevicesCommand(CLI::App& app) {
    app.add_subcommand("devices", "List OpenCL devices (the index, type or a name part selects one with --device)");
    return [] {
        const auto devices = listDevices();
        if (devices.empty()) throw deviceError("no OpenCL device found (install pocl-opencl-icd for the CPU, or a GPU driver)");
        const int chosen = selectDevice("").index;
        for (const DeviceInfo& d : devices)
            std::cout << fmt::format("{}{} {:<4} {} | {} | {}\n", d.index == chosen ? "*" : " ", d.index, d.type, d.name,
                                     d.platform, d.version);
        std::cout << "* = default\n";
    };
}

}  // namespace decalcomp::cli
