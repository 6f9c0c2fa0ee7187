// Profile JSON: the input as a --profile-file, then channel mapping of the data/ G-buffers' channel
// names through it, auto-detected and forced by name (detection rules, globs, {layer} patterns).
#include <filesystem>
#include <vector>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/profiles.hpp"
#include "fuzz/fuzz_support.hpp"
#include "fuzz/fuzz_targets.hpp"

namespace decalcomp::fuzz {

namespace fs = std::filesystem;

namespace {

// The G-buffers of data/, headers and channel names only: mapping never reads samples.
const std::vector<ExrImage>& sampleHeaders() {
    static const std::vector<ExrImage> images = [] {
        std::vector<ExrImage> found;
        for (const fs::directory_entry& set : fs::directory_iterator(DECALCOMP_DATA_DIR)) {
            const fs::path file = set.path() / "gbuffer.exr";
            if (!fs::is_regular_file(file)) continue;
            ExrImage image = readExr(file.string());
            for (ExrPart& part : image.parts)
                for (ExrChannel& channel : part.channels) channel.bytes = {};
            found.push_back(std::move(image));
        }
        return found;
    }();
    return images;
}

}  // namespace

void fuzzProfile(const std::uint8_t* data, std::size_t size) {
    const std::string path = writeScratchFile("profile.json", asText(data, size));
    std::vector<ChannelProfile> profiles;
    if (!inputErrorsAllowed([&] { profiles = loadProfileFile(path); })) return;
    MappingOptions options;
    options.profile_files = {path};
    std::vector<std::string> names{"auto"};
    for (std::size_t p = 0; p < profiles.size() && p < 4; ++p) names.push_back(profiles[p].name);  // bounded work
    for (const std::string& name : names) {
        options.profile = name;
        for (const ExrImage& image : sampleHeaders())
            inputErrorsAllowed([&] { (void)mapChannels(image, options); });
    }
}

}  // namespace decalcomp::fuzz
