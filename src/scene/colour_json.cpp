// Scene colour settings -> the colour space each texture is decoded from and the working space.
#include "scene/colour_json.hpp"

#include <fmt/format.h>

#include <utility>

namespace decalcomp::scene_detail {

const std::vector<std::string> kColourTopLevelKeys = {"working_space", "texture_colorspaces"};

namespace {

// What common configs call an sRGB-encoded texture and linear Rec.709 (the ACES studio and CG
// configs, their aliases, Blender's, OpenImageIO's built-in names), tried in this order, any case.
const std::vector<std::string> kSrgbTextureNames = {"sRGB - Texture", "srgb_tx", "Utility - sRGB - Texture",
                                                    "sRGB", "srgb_texture"};
const std::vector<std::string> kLinearRec709Names = {"Linear Rec.709 (sRGB)", "lin_rec709_srgb", "lin_rec709",
                                                     "Linear Rec.709", "Utility - Linear - sRGB", "lin_srgb",
                                                     "Linear"};
// A config this small is listed whole when a name is not in it.
constexpr std::size_t kMaxListedSpaces = 12;

std::string where(const JsonField& field) {
    return field.path().empty() ? field.file() : field.file() + ": " + field.path();
}

}  // namespace

SceneColour::SceneColour(const JsonField& root, std::string ocio_config) : ocio_file_(std::move(ocio_config)) {
    working_field_ = root.optional("working_space");
    if (const auto defaults = root.optional("texture_colorspaces")) {
        defaults->requireObject(R"(an object like {"integer": "sRGB - Texture", "float": "ACEScg"})");
        defaults->checkKeys({"integer", "float"});
        integer_field_ = defaults->optional("integer");
        float_field_ = defaults->optional("float");
        if (!integer_field_ && !float_field_) defaults->fail("expected 'integer' and/or 'float'");
    }
    // Settled now so that a wrong name fails before any texture is decoded.
    if (working_field_) settleWorkingSpace(*working_field_);
    else if (integer_field_ || float_field_) settleWorkingSpace(integer_field_ ? *integer_field_ : *float_field_);
}

const ColourConfig& SceneColour::config(const JsonField& asked_by) {
    if (!config_) config_ = ColourConfig::open(ocio_file_, where(asked_by));
    return *config_;
}

std::string SceneColour::requireSpace(const JsonField& field) {
    const std::string name = field.nonEmptyString("colour space name");
    const ColourConfig& colours = config(field);
    if (colours.hasSpace(name)) return name;
    const std::vector<std::string> names = colours.spaceNames();
    std::string guess = colours.firstSpaceOf({name});  // the same name in another case
    if (guess.empty()) guess = closestJsonKey(name, names).value_or("");
    if (!guess.empty())
        field.fail(fmt::format("'{}' is not a colour space of {} (did you mean '{}'?)", name, colours.file(), guess));
    if (names.size() <= kMaxListedSpaces)
        field.fail(fmt::format("'{}' is not a colour space of {} (it has: {})", name, colours.file(),
                               fmt::join(names, ", ")));
    field.fail(fmt::format("'{}' is not a colour space of {}", name, colours.file()));
}

void SceneColour::settleWorkingSpace(const JsonField& asked_by) {
    if (!working_.empty()) return;
    const ColourConfig& colours = config(asked_by);
    if (working_field_) {
        working_ = requireSpace(*working_field_);
    } else {
        working_ = colours.firstSpaceOf(kLinearRec709Names);
        if (working_.empty())
            asked_by.fail(fmt::format("{} has no linear Rec.709 space under a name decalcomp knows ({}): name the "
                                      "frames' colour space in the scene's 'working_space'",
                                      colours.file(), fmt::join(kLinearRec709Names, ", ")));
    }
    integer_default_ = integer_field_ ? requireSpace(*integer_field_) : colours.firstSpaceOf(kSrgbTextureNames);
    float_default_ = float_field_ ? requireSpace(*float_field_) : colours.firstSpaceOf(kLinearRec709Names);
}

std::optional<TextureColour> SceneColour::forTexture(const std::optional<JsonField>& colorspace) {
    if (colorspace) settleWorkingSpace(*colorspace);
    if (working_.empty()) return std::nullopt;  // no colour space anywhere: the built-in decode
    TextureColour colour{config_, integer_default_, float_default_, working_};
    if (colorspace) colour.integer_space = colour.float_space = requireSpace(*colorspace);
    return colour;
}

}  // namespace decalcomp::scene_detail
