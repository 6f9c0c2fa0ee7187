#pragma once
// A scene's colour management (docs/colour.md): its working space, the colour spaces of its
// textures, and the OpenColorIO config they are looked up in (internal).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/json_fields.hpp"
#include "textures/colour_config.hpp"

namespace decalcomp::scene_detail {

// Top-level keys the colour settings add to a scene.
extern const std::vector<std::string> kColourTopLevelKeys;

class SceneColour {
public:
    // Reads "working_space" and "texture_colorspaces" of `root`; `ocio_config` is --ocio ("" for
    // $OCIO). The config is opened when the scene first names a colour space.
    SceneColour(const JsonField& root, std::string ocio_config);

    // How to decode a colour map whose "colorspace" field is `colorspace` (absent: the defaults).
    // nullopt when the scene names no colour spaces at all: the built-in sRGB / linear decode.
    std::optional<TextureColour> forTexture(const std::optional<JsonField>& colorspace);

    const std::string& workingSpace() const { return working_; }  // "" when unmanaged
    std::string configFile() const { return config_ ? config_->file() : ""; }

private:
    const ColourConfig& config(const JsonField& asked_by);
    std::string requireSpace(const JsonField& name);
    void settleWorkingSpace(const JsonField& asked_by);

    std::string ocio_file_;
    std::optional<JsonField> working_field_, integer_field_, float_field_;
    std::shared_ptr<const ColourConfig> config_;
    std::string working_, integer_default_, float_default_;
};

}  // namespace decalcomp::scene_detail
