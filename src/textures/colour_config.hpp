#pragma once
// Colour management of decal textures: an OpenColorIO config read through OpenImageIO's
// ColorConfig (in the image module, images/image_codecs.hpp), and the conversion of decoded
// texels from a texture's colour space to the scene's working space (docs/colour.md).
#include <glm/vec4.hpp>

#include <memory>
#include <string>
#include <vector>

namespace decalcomp {

class ColourConfig {
public:
    // `file` empty: the config $OCIO names. Throws Error(Input) when neither names one, or the
    // config cannot be read; `asked_by` says what needed it ("scene.json: working_space").
    static std::shared_ptr<const ColourConfig> open(const std::string& file, const std::string& asked_by);
    ~ColourConfig();

    const std::string& file() const { return file_; }
    std::vector<std::string> spaceNames() const;
    bool hasSpace(const std::string& name) const;
    // The first of `candidates` the config defines, compared without case; "" if none.
    std::string firstSpaceOf(const std::vector<std::string>& candidates) const;

    // RGB of straight-alpha texels from `from` to `to` in place (alpha untouched). Throws
    // Error(Input) when OpenColorIO cannot build the conversion.
    void convert(std::vector<glm::vec4>& texels, const std::string& from, const std::string& to) const;

private:
    struct Impl;
    ColourConfig(std::string file, std::unique_ptr<Impl> impl);
    std::string file_;
    std::unique_ptr<Impl> impl_;
};

// How one texture's colour is decoded: from `integer_space` (8/16-bit files) or `float_space`
// (float files) to `working_space`. Equal names skip the conversion.
struct TextureColour {
    std::shared_ptr<const ColourConfig> config;
    std::string integer_space, float_space, working_space;
};

}  // namespace decalcomp
