// decalcomp: stamps decals into rendered G-buffer EXRs on an OpenCL device.
#include <fmt/format.h>
#include <malloc.h>

#include <climits>
#include <iostream>
#include <new>

#include "commands.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/temporary_files.hpp"
#include "usage_message.hpp"

namespace {

constexpr int kExitInternal = 1;

// A frame allocates and frees hundreds of megabytes of planes. glibc serves blocks that big with
// mmap and hands freed ones back to the kernel, so each frame faulted its memory in again, page by
// page, zeroed: half a batch's page faults, 8 % of `batch --io-only` on two cores
// (docs/decisions.md). Kept in the heap and never trimmed, freed planes serve the next frame.
// Set here, not in the library: a host application owns its allocator's settings.
void keepFreedFrameMemory() {
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
}

}  // namespace

int main(int argc, char** argv) {
    keepFreedFrameMemory();
    decalcomp::installTerminationCleanup();  // SIGINT/SIGTERM/SIGHUP: remove temporaries, exit 128+N
    CLI::App app{"decalcomp: composite decals into rendered G-buffer EXRs on an OpenCL device"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "decalcomp 0.1.0");
    std::function<void()> run;
    const auto composite = decalcomp::cli::addCompositeCommand(app);
    const auto info = decalcomp::cli::addInfoCommand(app);
    const auto devices = decalcomp::cli::addDevicesCommand(app);
    const auto batch = decalcomp::cli::addBatchCommand(app);
    const auto bake = decalcomp::cli::addBakeCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {  // --help, --version
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "decalcomp: error: " << decalcomp::cli::usageMessage(app, e, argc, argv) << "\n";
        return int(decalcomp::ErrorKind::Usage);
    }
    try {
        if (app.got_subcommand("composite")) composite();
        else if (app.got_subcommand("info")) info();
        else if (app.got_subcommand("devices")) devices();
        else if (app.got_subcommand("batch")) batch();
        else if (app.got_subcommand("bake")) bake();
        return 0;
    } catch (const decalcomp::Error& e) {
        std::cerr << "decalcomp: error: " << e.what() << "\n";
        return int(e.kind());
    } catch (const std::bad_alloc&) {  // inputs are size-checked first, so this is a full machine
        std::cerr << "decalcomp: error: out of memory: the inputs fit the memory limit but the machine has less "
                     "free; run fewer jobs at once, or lower batch --queue and --workers\n";
        return int(decalcomp::ErrorKind::Input);
    } catch (const std::exception& e) {
        std::cerr << "decalcomp: internal error: " << e.what() << "\n";
        return kExitInternal;
    }
}
