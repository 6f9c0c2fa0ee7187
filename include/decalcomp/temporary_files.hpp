#pragma once
// Temporary files this process is writing (".NAME.tmp-PID-N" beside each output), known to a
// termination signal handler so an interrupted run removes every one of them: outputs are written
// to a temporary and renamed into place, so an output that exists is always complete.
#include <string>
#include <utility>
#include <vector>

namespace decalcomp {

// ".NAME.tmp-PID-N" beside `target`, so the final rename stays within one file system; N counts
// the calls, so that two writes of one output in flight at once (a batch's frames that share an
// output) never share a temporary.
std::string temporaryPathFor(const std::string& target);

// How many temporaries may be live at once (createTemporary refuses more).
constexpr int kMaxLiveTemporaries = 256;

// Registers `path` as a live temporary, then creates it (empty, truncated if a stale one is
// there), so a signal arriving at any moment after this call finds it and removes it. Returns the
// name to open it by for writing: the registry holds the file open until it is committed or
// discarded, and the name reaches it through that descriptor (/proc/self/fd/N), so a write that
// starts after a signal removed the temporary cannot bring it back. Commit and discard take
// `path`. Throws Error(Output) naming `output` (what the temporary will become) when it cannot be
// created, the path is too long to keep, or too many temporaries are live at once
// (kMaxLiveTemporaries).
std::string createTemporary(const std::string& path, const std::string& output);

// Renames every temporary onto its final path, as one group: a termination signal arriving in
// the middle finishes the renames instead of leaving some outputs of the group in place and others
// removed. On a failed rename the temporaries not yet renamed are removed and Error(Output) names
// the final path (the group's earlier renames stay).
void commitTemporaries(const std::vector<std::pair<std::string, std::string>>& temporary_to_final);

// Removes the temporary and forgets it.
void discardTemporary(const std::string& path) noexcept;

// How many temporaries are live (registered and neither committed nor discarded); for tests.
int liveTemporaryCount() noexcept;

// Async-signal-safe: removes every live temporary (finishing the renames of a group whose commit
// had begun). For a host application's own signal handler; the one below calls it.
void removeLiveTemporaries() noexcept;

// Installs handlers for SIGINT, SIGTERM and SIGHUP that call removeLiveTemporaries, print one line
// naming the signal and exit with 128 + the signal number (130, 143, 129). A signal the process
// started with ignored (nohup, a background job) stays ignored. Call once, before starting threads.
void installTerminationCleanup();

}  // namespace decalcomp
