// OpenColorIO through OpenImageIO's ColorConfig: which spaces a config has, and conversions.
#include "textures/colour_config.hpp"

#include <OpenImageIO/color.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "decalcomp/error.hpp"
#include "decalcomp/input_file.hpp"
#include "io/exr_layout.hpp"

namespace decalcomp {
namespace {

std::string lowered(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

// OpenColorIO's reason on one line, or a placeholder when it gave none.
std::string reason(const std::string& message) {
    const std::string line = io::oneLine(message);
    return line.empty() ? "unknown error" : line;
}

}  // namespace

struct ColourConfig::Impl {
    explicit Impl(const std::string& file) : config(file) {}
    OIIO::ColorConfig config;
};

ColourConfig::ColourConfig(std::string file, std::unique_ptr<Impl> impl) : file_(std::move(file)), impl_(std::move(impl)) {}
ColourConfig::~ColourConfig() = default;

std::shared_ptr<const ColourConfig> ColourConfig::open(const std::string& file, const std::string& asked_by) {
    std::string path = file;
    if (path.empty()) {
        const char* env = std::getenv("OCIO");
        if (env) path = env;
    }
    // Without a config OpenImageIO would fall back to a few built-in names; a scene that names
    // colour spaces means a studio's config, so its absence is an error, not a guess.
    if (path.empty())
        throw inputError(fmt::format("{}: colour spaces need an OpenColorIO config: give --ocio FILE or set $OCIO",
                                     asked_by));
    requireInputFile(path, "OpenColorIO config");
    auto impl = std::make_unique<Impl>(path);
    if (impl->config.has_error() || impl->config.getNumColorSpaces() <= 0) {
        const std::string why = impl->config.has_error() ? reason(impl->config.geterror()) : "it defines no colour spaces";
        throw inputError(fmt::format("{}: cannot use the OpenColorIO config: {}", path, why));
    }
    return std::shared_ptr<const ColourConfig>(new ColourConfig(path, std::move(impl)));
}

std::vector<std::string> ColourConfig::spaceNames() const { return impl_->config.getColorSpaceNames(); }

bool ColourConfig::hasSpace(const std::string& name) const {
    const std::vector<std::string> names = spaceNames();
    return std::find(names.begin(), names.end(), name) != names.end();
}

std::string ColourConfig::firstSpaceOf(const std::vector<std::string>& candidates) const {
    const std::vector<std::string> names = spaceNames();
    for (const std::string& candidate : candidates)
        for (const std::string& name : names)
            if (lowered(name) == lowered(candidate)) return name;
    return "";
}

void ColourConfig::convert(std::vector<glm::vec4>& texels, const std::string& from, const std::string& to) const {
    if (from == to || texels.empty()) return;
    const OIIO::ColorProcessorHandle processor = impl_->config.createColorProcessor(from, to);
    if (!processor)
        throw inputError(fmt::format("{}: OpenColorIO cannot convert '{}' to '{}': {}", file_, from, to,
                                     reason(impl_->config.geterror())));
    if (processor->isNoOp()) return;
    // One row of RGBA texels: OpenColorIO converts the first three channels and keeps alpha.
    processor->apply(&texels[0].r, int(texels.size()), 1, 4, sizeof(float), sizeof(glm::vec4),
                     OIIO::stride_t(sizeof(glm::vec4) * texels.size()));
}

}  // namespace decalcomp
