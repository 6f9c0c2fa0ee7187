// The calling thread's CPU time, for the batch's per-stage CPU figures (batch --timing).
#pragma once

#include <cstdint>
#include <ctime>

namespace decalcomp {

// Nanoseconds of CPU this thread has used (CLOCK_THREAD_CPUTIME_ID).
inline std::int64_t threadCpuNs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return std::int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

}  // namespace decalcomp
