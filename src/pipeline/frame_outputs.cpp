// Where a frame's outputs go, and writing them all or none.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>
#include <utility>

#include "decalcomp/error.hpp"
#include "decalcomp/pipeline.hpp"
#include "decalcomp/temporary_files.hpp"

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

namespace {

// Where a path that may not exist yet would land: symbolic links followed, dangling ones too
// (writing through a dangling link creates its target), up to a bound that stops link loops.
fs::path landingPath(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::absolute(path, ec);
    for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
        const fs::path target = fs::read_symlink(p, ec);
        if (ec) break;
        p = target.is_absolute() ? target : p.parent_path() / target;
    }
    return fs::weakly_canonical(p, ec).lexically_normal();
}

}  // namespace

bool sameFile(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
    return landingPath(a) == landingPath(b);
}

bool hasExtension(const std::string& path, const std::string& extension) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == extension;
}

void checkRunFiles(const RunFiles& files, bool overwrite_inputs) {
    for (const std::string& output : files.exr_outputs)
        if (!hasExtension(output, ".exr"))
            throw Error(ErrorKind::Usage, fmt::format("{}: the output is written as OpenEXR; give it an .exr name", output));
    std::vector<std::pair<std::string, std::string>> outputs;  // path, what it is
    for (const std::string& output : files.exr_outputs) outputs.emplace_back(output, "output");
    if (!files.preview.empty()) outputs.emplace_back(files.preview, "preview");
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const auto& [path, what] = outputs[i];
        for (std::size_t j = 0; j < i; ++j)
            if (sameFile(path, outputs[j].first))
                throw Error(ErrorKind::Usage, fmt::format("{}: the {} would replace the {} {}", path, what,
                                                          outputs[j].second, outputs[j].first));
        for (const std::string& input : files.exr_inputs)
            if (sameFile(path, input) && (what == "preview" || !overwrite_inputs))
                throw Error(ErrorKind::Usage,
                            fmt::format("{}: the {} would replace the input {}{}", path, what, input,
                                        what == "preview" ? "" : "; pass --overwrite-input to replace it"));
        for (const std::string& read : files.other_reads)
            if (!read.empty() && sameFile(path, read))
                throw Error(ErrorKind::Usage, fmt::format("{}: the {} would replace {}, which this run reads", path,
                                                          what, read));
    }
}

namespace {

// Creates the missing folders above `file`; returns them, outermost first, so a failed write can
// take back exactly what it made. Error(Output) naming `file` when one cannot be made.
std::vector<fs::path> createMissingFolders(const std::string& file) {
    std::vector<fs::path> missing;
    std::error_code ec;
    for (fs::path folder = fs::path(file).parent_path(); !folder.empty() && !fs::exists(folder, ec);
         folder = folder.parent_path())
        missing.insert(missing.begin(), folder);
    for (const fs::path& folder : missing)
        if (!fs::create_directory(folder, ec) && ec)
            throw outputError(fmt::format("{}: cannot create the folder {}: {}", file, folder.string(), ec.message()));
    return missing;
}

}  // namespace

StagedOutputs::StagedOutputs(StagedOutputs&& other) noexcept
    : temporaries_(std::exchange(other.temporaries_, {})),
      created_folders_(std::exchange(other.created_folders_, {})),
      stats_(other.stats_) {}

StagedOutputs& StagedOutputs::operator=(StagedOutputs&& other) noexcept {
    if (this != &other) {
        discard();
        temporaries_ = std::exchange(other.temporaries_, {});
        created_folders_ = std::exchange(other.created_folders_, {});
        stats_ = other.stats_;
    }
    return *this;
}

void StagedOutputs::commit() {
    commitTemporaries(std::exchange(temporaries_, {}));  // on a failure it has taken back the temporaries itself
    created_folders_.clear();
}

void StagedOutputs::discard() noexcept {
    for (const auto& [temporary, final_path] : temporaries_) discardTemporary(temporary);
    temporaries_.clear();
    std::error_code ec;
    for (auto folder = created_folders_.rbegin(); folder != created_folders_.rend(); ++folder)
        fs::remove(*folder, ec);  // only if empty
    created_folders_.clear();
}

StagedOutputs stageOutputsTogether(const std::vector<PendingOutput>& outputs, const std::string* preview,
                                   const std::function<void(const std::string&)>& write_preview) {
    // Everything goes to registered temporaries first (decalcomp/temporary_files.hpp), renamed as one
    // group by commit(), so a failed write or a termination signal leaves none of the outputs behind.
    StagedOutputs staged;  // discards what it holds if a write below throws
    auto createFoldersFor = [&](const std::string& file) {
        for (fs::path& folder : createMissingFolders(file)) staged.created_folders_.push_back(std::move(folder));
    };
    // Every record is allocated before its temporary is created, so that a created temporary is
    // always held (and so discarded on a failure).
    staged.temporaries_.reserve(outputs.size() + (preview ? 1 : 0));
    if (preview) {
        createFoldersFor(*preview);
        std::pair<std::string, std::string> entry{temporaryPathFor(*preview), *preview};
        const std::string opening_name = createTemporary(entry.first, *preview);
        staged.temporaries_.push_back(std::move(entry));
        write_preview(opening_name);
    }
    for (const PendingOutput& output : outputs) {
        createFoldersFor(output.path);
        std::string final_path = output.path;
        staged.temporaries_.emplace_back(writeExrTemporary(*output.image, output.path, &staged.stats_),
                                         std::move(final_path));
    }
    // the preview, written first, is renamed after the EXRs
    if (preview) std::rotate(staged.temporaries_.begin(), staged.temporaries_.begin() + 1, staged.temporaries_.end());
    return staged;
}

ChunkWriteStats writeOutputsTogether(const std::vector<PendingOutput>& outputs, const std::string* preview,
                                     const std::function<void(const std::string&)>& write_preview) {
    StagedOutputs staged = stageOutputsTogether(outputs, preview, write_preview);
    staged.commit();
    return staged.stats();
}

}  // namespace decalcomp
