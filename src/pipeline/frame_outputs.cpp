// Where a frame's outputs go, and writing them all or none.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <set>

#include "decalcomp/error.hpp"
#include "decalcomp/pipeline.hpp"

namespace decalcomp {

namespace fs = std::filesystem;

bool isOutputFolder(const std::string& path) {
    std::error_code ec;
    return (!path.empty() && path.back() == '/') || fs::is_directory(path, ec);
}

std::map<int, std::string> outputPaths(const std::vector<ExrImage>& files, const ChannelMapping& mapping,
                                       const std::vector<Attribute>& attributes, const std::string& output) {
    std::set<int> changed;
    for (Attribute attribute : attributes)
        if (auto it = mapping.attributes.find(attribute); it != mapping.attributes.end())
            for (const ChannelRef& ref : it->second) changed.insert(ref.file);
    std::map<int, std::string> paths;
    if (changed.empty()) return paths;
    const bool folder = isOutputFolder(output);
    if (changed.size() > 1 && !folder) {
        std::vector<std::string> names;
        for (int f : changed) names.push_back(files[std::size_t(f)].path);
        throw Error(ErrorKind::Usage,
                    fmt::format("{}: the composited channels live in {} files ({}): give -o an output folder "
                                "(an existing one, or a path ending in '/')",
                                output, changed.size(), fmt::join(names, ", ")));
    }
    std::map<std::string, int> names;
    for (int f : changed) {
        const std::string& input = files[std::size_t(f)].path;
        if (!folder) {
            paths[f] = output;
            continue;
        }
        const std::string name = fs::path(input).filename().string();
        if (auto it = names.find(name); it != names.end())
            throw Error(ErrorKind::Usage, fmt::format("{}: {} and {} would both be written as {}", output,
                                                      files[std::size_t(it->second)].path, input, name));
        names[name] = f;
        paths[f] = (fs::path(output) / name).string();
    }
    return paths;
}

void checkNotOverwritingInput(const std::string& input, const std::string& output, bool allowed) {
    std::error_code ec;
    const bool same = fs::exists(output, ec) && fs::equivalent(input, output, ec);
    if (same && !allowed)
        throw Error(ErrorKind::Usage, fmt::format("{}: output is the input file; pass --overwrite-input to replace it", output));
}

void writeOutputsTogether(const std::vector<PendingOutput>& outputs, const std::string* preview,
                          const std::function<void(const std::string&)>& write_preview) {
    // Everything goes to temporary names first, so a failed write leaves none of the outputs behind.
    std::string preview_tmp;
    std::vector<std::pair<std::string, std::string>> written;  // temporary, final
    try {
        if (preview) {
            preview_tmp = *preview + ".partial.png";
            write_preview(preview_tmp);
        }
        for (const PendingOutput& output : outputs) {
            const fs::path parent = fs::path(output.path).parent_path();
            std::error_code ec;
            if (output.create_folder && !parent.empty()) fs::create_directories(parent, ec);
            written.emplace_back(writeExrTemporary(*output.image, output.path), output.path);
        }
        for (const auto& [temporary, final_path] : written) commitExrTemporary(temporary, final_path);
    } catch (...) {
        for (const auto& [temporary, final_path] : written) discardExrTemporary(temporary);
        if (!preview_tmp.empty()) {
            std::error_code ec;
            fs::remove(preview_tmp, ec);
        }
        throw;
    }
    if (!preview_tmp.empty()) {
        std::error_code ec;
        fs::rename(preview_tmp, *preview, ec);
        if (ec) {
            fs::remove(preview_tmp, ec);
            throw outputError(fmt::format("{}: cannot write preview: {}", *preview, ec.message()));
        }
    }
}

}  // namespace decalcomp
