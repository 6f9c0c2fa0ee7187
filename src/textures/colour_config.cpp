// OpenColorIO through OpenImageIO's ColorConfig (in the image module): which spaces a config has,
// and conversions.
#include "textures/colour_config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "decalcomp/error.hpp"
#include "decalcomp/input_file.hpp"
#include "images/image_codecs.hpp"

namespace decalcomp {
namespace {

std::string lowered(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

}  // namespace

struct ColourConfig::Impl {
    std::unique_ptr<images::ColourConfigFile> config;
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
    const images::Codecs& codecs = images::imageCodecs(ErrorKind::Input, path);
    auto impl = std::make_unique<Impl>();
    std::string why;
    impl->config = codecs.openColourConfig(path, why);
    if (!impl->config) throw inputError(fmt::format("{}: cannot use the OpenColorIO config: {}", path, why));
    return std::shared_ptr<const ColourConfig>(new ColourConfig(path, std::move(impl)));
}

std::vector<std::string> ColourConfig::spaceNames() const { return impl_->config->spaceNames(); }

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
    static_assert(sizeof(glm::vec4) == 4 * sizeof(float), "texels are four packed floats");
    const std::string failure = impl_->config->convert(&texels[0].r, texels.size(), from, to);
    if (!failure.empty())
        throw inputError(fmt::format("{}: OpenColorIO cannot convert '{}' to '{}': {}", file_, from, to, failure));
}

}  // namespace decalcomp
