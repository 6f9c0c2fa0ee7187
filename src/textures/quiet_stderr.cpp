#include "textures/quiet_stderr.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <mutex>

namespace decalcomp {

namespace {
std::mutex g_stderr_mutex;
}

QuietStderr::QuietStderr() {
    g_stderr_mutex.lock();
    std::fflush(stderr);
    const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (null_fd < 0) return;  // nothing to redirect to: leave stderr as it is
    saved_ = ::dup(STDERR_FILENO);
    if (saved_ >= 0) ::dup2(null_fd, STDERR_FILENO);
    ::close(null_fd);
}

QuietStderr::~QuietStderr() {
    std::fflush(stderr);
    if (saved_ >= 0) {
        ::dup2(saved_, STDERR_FILENO);
        ::close(saved_);
    }
    g_stderr_mutex.unlock();
}

}  // namespace decalcomp
