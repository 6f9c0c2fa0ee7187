// libFuzzer's entry point for one target, chosen at build time (DECALCOMP_FUZZ_TARGET, e.g.
// fuzzScene; tests/fuzz/CMakeLists.txt). An exception that escapes the target is a finding: it
// is printed and the process aborts, so libFuzzer saves the input like any crash.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <typeinfo>

#include "fuzz/fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        decalcomp::fuzz::DECALCOMP_FUZZ_TARGET(data, size);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "decalcomp fuzz: %s escaped: %s\n", typeid(e).name(), e.what());
        std::abort();
    } catch (...) {
        std::fprintf(stderr, "decalcomp fuzz: a non-std exception escaped\n");
        std::abort();
    }
    return 0;
}
