#include "decalcomp/input_file.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "decalcomp/error.hpp"

namespace decalcomp {

void requireInputFile(const std::string& path, const std::string& what) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (path.empty()) throw inputError(fmt::format("the {} path is empty", what));
    if (!fs::exists(status))
        throw inputError(fmt::format("{}: cannot open the {}: no such file", path, what));
    if (fs::is_directory(status))
        throw inputError(fmt::format("{}: is a folder, not a file; give the {} itself", path, what));
    if (!fs::is_regular_file(status) && !fs::is_fifo(status) && !fs::is_character_file(status))
        throw inputError(fmt::format("{}: is not a regular file; give the {} itself", path, what));
    if (::access(path.c_str(), R_OK) != 0)
        throw inputError(fmt::format("{}: cannot open the {}: {}", path, what, std::strerror(errno)));
}

}  // namespace decalcomp
