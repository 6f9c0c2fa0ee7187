#pragma once
// OpenEXR's core C API (openexr.h) behind one owner per context: read contexts (header and chunk
// table, no pixel memory) and write contexts. OpenEXR's messages are kept for our one-line errors
// instead of going to stderr (internal).
#include <OpenEXR/openexr.h>

#include <string>

namespace decalcomp::io {

class CoreContext {
public:
    // ReadAsStored reads as Read does, but takes the chunk table as the file stores it: where its
    // offsets are invalid, OpenEXR's core otherwise rebuilds the table by scanning the file, while
    // its C++ reader refuses the file, and a decoder should not read pixels from a guessed table.
    enum class Mode { Read, ReadAsStored, Write };
    // Read, ReadAsStored: Error(Input) naming `path` when OpenEXR cannot parse it. Write: creates
    // (replaces) `path`, Error(Output) on failure. Messages name `name` (default: `path`).
    CoreContext(const std::string& path, Mode mode, const std::string& name = {});
    // Reads a file held in memory (`bytes` must outlive the context); `name` names it in messages.
    CoreContext(const std::string& name, const std::string& bytes);
    ~CoreContext();
    CoreContext(const CoreContext&) = delete;
    CoreContext& operator=(const CoreContext&) = delete;

    exr_context_t context() const { return context_; }
    const std::string& path() const { return path_; }
    // OpenEXR's last message on this thread (then forgotten), else its text for `result`.
    std::string reason(exr_result_t result) const;
    // Throws Error (Input for read contexts, Output for write ones) "PATH: part P: FIELD: reason".
    void require(exr_result_t result, int part, const std::string& field) const;
    // Finishes a write context: flushes the chunk tables and closes the file; throws as require().
    void finish();

private:
    std::string path_;
    Mode mode_;
    exr_context_t context_ = nullptr;
    static void remember(exr_const_context_t context, exr_result_t, const char* message);
};

}  // namespace decalcomp::io
