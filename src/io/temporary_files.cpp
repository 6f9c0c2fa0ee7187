// The registry of live temporary files and the termination signal handler that removes them.
//
// The handler may interrupt any thread at any point, including one that is registering, creating
// or committing a temporary, so it touches only this fixed table of slots: lock-free atomics and
// paths copied in before a slot is published. It takes no lock and allocates nothing; unlink,
// rename, write, nanosleep and _exit are async-signal-safe. Normal threads find a path's slot
// through a mutex-protected index that the handler never reads.
#include "decalcomp/temporary_files.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <mutex>

#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

constexpr int kSlotCount = kMaxLiveTemporaries;
constexpr std::size_t kPathCapacity = 4096;  // PATH_MAX on Linux, terminating NUL included

// A slot's life: Free -> Claimed (its owner copies the path in) -> Creating (published; the file is
// being created) -> Live -> Free again when committed or discarded. Taken: the handler has it.
enum SlotState : int { Free, Claimed, Creating, Live, Taken };
// A commit group's state, kept in its first slot: Open until its renames begin (Committing); the
// handler turns every Open group Abandoned first, so a group either renames completely or not at all.
enum CommitState : int { Open, Committing, Abandoned };

struct Slot {
    std::atomic<int> state{Free};
    std::atomic<pid_t> owner{0};    // the thread creating the file
    std::atomic<int> group{-1};     // the slot holding this temporary's commit group state; -1: none
    std::atomic<int> commit{Open};  // as a group's first slot
    std::atomic<int> fd{-1};        // held open from creation to release; writers open the file through it
    char path[kPathCapacity] = {};
    char final_path[kPathCapacity] = {};  // the rename target, set before its group commits
};

static_assert(std::atomic<int>::is_always_lock_free && std::atomic<pid_t>::is_always_lock_free &&
                  std::atomic<bool>::is_always_lock_free,
              "the signal handler needs lock-free atomics");

Slot g_slots[kSlotCount];
std::atomic<bool> g_terminating{false};  // set first by removeLiveTemporaries; nothing new starts after it
std::atomic<bool> g_handling{false};     // a termination handler is running (on some thread)

// path -> slot, for normal threads only.
std::mutex g_index_mutex;
std::map<std::string, int> g_index;

// The process is terminating (removeLiveTemporaries ran): this thread must not create or rename
// anything, so it waits for the handler's _exit.
[[noreturn]] void waitForExit() {
    for (;;) ::pause();
}

void copyPath(char (&to)[kPathCapacity], const std::string& from) { std::memcpy(to, from.c_str(), from.size() + 1); }

int claimSlot() {
    for (int i = 0; i < kSlotCount; ++i) {
        int expected = Free;
        if (g_slots[i].state.compare_exchange_strong(expected, Claimed)) {
            g_slots[i].group = -1;
            g_slots[i].commit = Open;
            return i;
        }
    }
    return -1;
}

int slotOf(const std::string& path) {
    std::lock_guard lock(g_index_mutex);
    const auto it = g_index.find(path);
    return it == g_index.end() ? -1 : it->second;
}

// Forgets a temporary that is gone (renamed or removed). A slot the handler has taken stays taken.
void release(int slot, const std::string& path) {
    {
        std::lock_guard lock(g_index_mutex);
        g_index.erase(path);
    }
    if (const int fd = g_slots[slot].fd.exchange(-1); fd >= 0) ::close(fd);
    int live = Live;
    g_slots[slot].state.compare_exchange_strong(live, Free);
}

// Waits, for at most two seconds, while another thread creates the slot's file: it is about to be
// Live (or to give the slot up, having seen g_terminating). Returns the state it ends in.
int waitWhileCreating(const Slot& slot) {
    const timespec millisecond{0, 1'000'000};
    int state = slot.state;
    for (int i = 0; i < 2000 && state == Creating; ++i) {
        ::nanosleep(&millisecond, nullptr);
        state = slot.state;
    }
    return state;
}

// Removes the slot's temporary, or renames it into place when its group's commit had begun.
void removeSlot(Slot& slot, pid_t self) {
    int state = slot.state;
    if (state == Creating && slot.owner != self) state = waitWhileCreating(slot);
    if (state != Live && state != Creating) return;  // Free, Taken, or Claimed (its owner stops before creating)
    if (!slot.state.compare_exchange_strong(state, Taken)) return;  // released by its owner just now
    const int group = slot.group;
    if (group >= 0 && g_slots[group].commit == Committing && ::rename(slot.path, slot.final_path) == 0) return;
    ::unlink(slot.path);  // ENOENT when its owner renamed or removed it already
}

const char* signalName(int signal) {
    switch (signal) {
        case SIGINT:
            return "SIGINT";
        case SIGTERM:
            return "SIGTERM";
        case SIGHUP:
            return "SIGHUP";
        default:
            return "a signal";
    }
}

void writeStderr(const char* text) {
    if (::write(STDERR_FILENO, text, std::strlen(text)) < 0) {
        // Nothing to do: the exit status still says why the run ended.
    }
}

void onTerminationSignal(int signal) {
    if (g_handling.exchange(true)) waitForExit();  // another thread's handler cleans up and exits
    removeLiveTemporaries();
    writeStderr("decalcomp: interrupted by ");
    writeStderr(signalName(signal));
    writeStderr(": unfinished outputs removed\n");
    ::_exit(128 + signal);
}

constexpr int kTerminationSignals[] = {SIGINT, SIGTERM, SIGHUP};

}  // namespace

std::string temporaryPathFor(const std::string& target) {
    static std::atomic<unsigned> calls{0};
    const std::filesystem::path path(target);
    return (path.parent_path() / fmt::format(".{}.tmp-{}-{}", path.filename().string(), ::getpid(), calls++)).string();
}

// The name a writer opens a temporary by: the descriptor the registry holds, through /proc, so a
// writer that opens it after the handler unlinked its name (the handler runs on one thread while
// the others go on until _exit) writes to the unnamed file instead of creating the name again.
std::string openingName(int fd, const std::string& path) {
    static const bool proc = ::access("/proc/self/fd", X_OK) == 0;
    return proc ? fmt::format("/proc/self/fd/{}", fd) : path;
}

std::string createTemporary(const std::string& path, const std::string& output) {
    if (path.size() >= kPathCapacity)
        throw outputError(fmt::format("{}: cannot write: the path is longer than {} bytes; use a shorter one", output,
                                      kPathCapacity - 1));
    const int i = claimSlot();
    if (i < 0)
        throw outputError(fmt::format("{}: cannot write: more than {} temporary files are being written at once",
                                      output, kSlotCount));
    Slot& slot = g_slots[i];
    copyPath(slot.path, path);
    slot.owner = ::gettid();
    try {
        std::lock_guard lock(g_index_mutex);
        g_index[path] = i;
    } catch (...) {
        slot.state = Free;
        throw;
    }
    // Published before the file exists, so a signal from here on finds it (the handler waits for
    // a file being created on another thread).
    slot.state = Creating;
    if (g_terminating) {
        int creating = Creating;
        slot.state.compare_exchange_strong(creating, Free);
        waitForExit();
    }
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    const int error = errno;
    slot.fd = fd;
    int creating = Creating;
    if (!slot.state.compare_exchange_strong(creating, Live)) waitForExit();  // the handler took it
    if (fd < 0) {
        release(i, path);
        throw outputError(fmt::format("{}: cannot write {}: {}; check that the folder exists and is writable", output,
                                      std::filesystem::path(path).filename().string(), std::strerror(error)));
    }
    try {
        return openingName(fd, path);
    } catch (...) {  // out of memory: nothing may stay behind that the caller does not hold
        ::unlink(path.c_str());
        release(i, path);
        throw;
    }
}

void commitTemporaries(const std::vector<std::pair<std::string, std::string>>& temporary_to_final) {
    if (temporary_to_final.empty()) return;
    std::vector<int> slots;
    for (const auto& [temporary, final_path] : temporary_to_final) {
        if (final_path.size() >= kPathCapacity)
            throw outputError(fmt::format("{}: cannot write: the path is longer than {} bytes; use a shorter one",
                                          final_path, kPathCapacity - 1));
        slots.push_back(slotOf(temporary));  // -1: not registered here; renamed all the same
    }
    int leader = -1;
    for (std::size_t k = 0; k < slots.size(); ++k) {
        if (slots[k] < 0) continue;
        if (leader < 0) leader = slots[k];
        copyPath(g_slots[slots[k]].final_path, temporary_to_final[k].second);
        g_slots[slots[k]].group = leader;
    }
    // From here on the handler finishes these renames instead of removing the temporaries.
    int open = Open;
    if (leader >= 0 && !g_slots[leader].commit.compare_exchange_strong(open, Committing)) waitForExit();
    std::size_t renamed = 0;
    std::error_code ec;
    for (; renamed < temporary_to_final.size(); ++renamed) {
        const auto& [temporary, final_path] = temporary_to_final[renamed];
        std::filesystem::rename(temporary, final_path, ec);
        if (ec) break;
    }
    if (leader >= 0) g_slots[leader].commit = Open;  // before any slot is released (and reused)
    for (std::size_t k = 0; k < slots.size(); ++k) {
        if (k >= renamed) {
            std::error_code ignored;
            std::filesystem::remove(temporary_to_final[k].first, ignored);
        }
        if (slots[k] >= 0) release(slots[k], temporary_to_final[k].first);
    }
    if (ec) throw outputError(fmt::format("{}: cannot write: {}", temporary_to_final[renamed].second, ec.message()));
}

void discardTemporary(const std::string& path) noexcept {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    try {
        if (const int slot = slotOf(path); slot >= 0) release(slot, path);
    } catch (...) {
        // std::mutex::lock failing: the slot stays registered, and the handler would only unlink
        // a file that is gone.
    }
}

int liveTemporaryCount() noexcept {
    int count = 0;
    for (const Slot& slot : g_slots) count += slot.state == Creating || slot.state == Live;
    return count;
}

void removeLiveTemporaries() noexcept {
    g_terminating = true;
    // No group may begin its renames from now on; those that began are finished below.
    for (Slot& slot : g_slots) {
        int open = Open;
        slot.commit.compare_exchange_strong(open, Abandoned);
    }
    const pid_t self = ::gettid();
    for (Slot& slot : g_slots) removeSlot(slot, self);
}

void installTerminationCleanup() {
    for (int signal : kTerminationSignals) {
        struct sigaction current {};
        if (::sigaction(signal, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) continue;  // nohup, `cmd &`
        struct sigaction action {};
        action.sa_handler = onTerminationSignal;
        sigemptyset(&action.sa_mask);
        for (int other : kTerminationSignals) sigaddset(&action.sa_mask, other);
        ::sigaction(signal, &action, nullptr);
    }
}

}  // namespace decalcomp
