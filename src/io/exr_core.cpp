#include "io/exr_core.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "decalcomp/error.hpp"

namespace decalcomp::io {

namespace {

// OpenEXR reports on the thread of the failing call, and write contexts hold their lock while
// they report (exr_get_user_data would wait for it forever), so the message goes to the thread.
thread_local std::string last_message;

}  // namespace

void CoreContext::remember(exr_const_context_t, exr_result_t, const char* message) {
    if (message) last_message = message;
}

CoreContext::CoreContext(const std::string& path, Mode mode, const std::string& name)
    : path_(name.empty() ? path : name), mode_(mode) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = &CoreContext::remember;  // instead of OpenEXR's own stderr lines
    if (mode == Mode::ReadAsStored) init.flags |= EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    last_message.clear();
    const bool reading = mode != Mode::Write;
    const exr_result_t result = reading ? exr_start_read(&context_, path.c_str(), &init)
                                        : exr_start_write(&context_, path.c_str(), EXR_WRITE_FILE_DIRECTLY, &init);
    if (result == EXR_ERR_SUCCESS && reading && !last_message.empty()) {
        // The core reader skipped something it objected to (a duplicated attribute, say) where
        // OpenEXR's C++ reader takes the last copy: the two would read different files, and every
        // size check made here would be about the wrong one (found by fuzzing).
        exr_finish(&context_);
        throw inputError(fmt::format("{}: header: {}; the header is corrupt", path_, reason(result)));
    }
    if (result == EXR_ERR_SUCCESS) return;
    const std::string text = fmt::format("{}: cannot {}: {}", path_, reading ? "read" : "write", reason(result));
    if (reading) throw inputError(text);
    throw outputError(text);
}

namespace {

int64_t readMemory(exr_const_context_t, void* user, void* buffer, uint64_t size, uint64_t offset,
                   exr_stream_error_func_ptr_t) {
    const std::string& bytes = *static_cast<const std::string*>(user);
    if (offset >= bytes.size()) return 0;
    const uint64_t n = std::min<uint64_t>(size, bytes.size() - offset);
    std::memcpy(buffer, bytes.data() + offset, n);
    return int64_t(n);
}

int64_t memorySize(exr_const_context_t, void* user) { return int64_t(static_cast<const std::string*>(user)->size()); }

}  // namespace

CoreContext::CoreContext(const std::string& name, const std::string& bytes) : path_(name), mode_(Mode::Read) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = &CoreContext::remember;
    init.user_data = const_cast<std::string*>(&bytes);  // only read
    init.read_fn = &readMemory;
    init.size_fn = &memorySize;
    const exr_result_t result = exr_start_read(&context_, name.c_str(), &init);
    if (result != EXR_ERR_SUCCESS) throw outputError(fmt::format("{}: cannot read back: {}", name, reason(result)));
}

CoreContext::~CoreContext() {
    if (context_) exr_finish(&context_);
}

std::string CoreContext::reason(exr_result_t result) const {
    std::string message = last_message.empty() ? exr_get_default_error_message(result) : last_message;
    last_message.clear();
    return message;
}

void CoreContext::require(exr_result_t result, int part, const std::string& field) const {
    if (result == EXR_ERR_SUCCESS) return;
    const std::string text = fmt::format("{}: part {}: {}: {}", path_, part, field, reason(result));
    if (mode_ != Mode::Write) throw inputError(text);
    throw outputError(text);
}

void CoreContext::finish() {
    const exr_result_t result = exr_finish(&context_);
    context_ = nullptr;
    if (result != EXR_ERR_SUCCESS) {
        const std::string text = fmt::format("{}: cannot finish: {}", path_, reason(result));
        if (mode_ != Mode::Write) throw inputError(text);
        throw outputError(text);
    }
}

}  // namespace decalcomp::io
