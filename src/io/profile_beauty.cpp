#include "profile_beauty.hpp"

#include <fmt/format.h>

#include "decalcomp/profiles.hpp"

namespace decalcomp {

namespace {

// Spellings of one RGB pass: a pattern with a component group ("{layer}.DiffDir.{R,G,B}"), or an
// array of them, one per naming generation.
std::vector<std::string> parseRgbSpellings(const JsonField& value) {
    std::vector<JsonField> items;
    if (value.isArray()) {
        if (value.size() == 0) value.fail("expected a non-empty array of channel patterns");
        items = value.elements();
    } else {
        items.push_back(value);
    }
    std::vector<std::string> spellings;
    for (const JsonField& item : items) {
        const std::string pattern = item.nonEmptyString("channel pattern");
        std::vector<std::string> channels;
        try {
            channels = expandChannelPattern(pattern);
        } catch (const Error& e) {
            item.fail(e.what());
        }
        if (channels.size() != 3)
            item.fail(fmt::format("'{}': expected an RGB pattern with a component group like {{R,G,B}}", pattern));
        spellings.push_back(pattern);
    }
    return spellings;
}

BeautyLobe parseLobe(const JsonField& value) {
    value.requireObject("a lobe object");
    value.checkKeys({"name", "colour", "direct", "indirect", "total", "comment"});
    BeautyLobe lobe;
    lobe.name = value.required("name").nonEmptyString("lobe name");
    // "albedo": the attribute decals change; "none": a colour no pass shows; else its pass.
    const JsonField colour = value.required("colour", "\"albedo\", \"none\", or the lobe's colour pass");
    const bool word = colour.value().is_string() && (colour.string() == "albedo" || colour.string() == "none");
    if (word) lobe.follows_albedo = colour.string() == "albedo";
    else lobe.colour = BeautyTerm{"colour", parseRgbSpellings(colour)};
    for (const char* role : {"direct", "indirect", "total"})
        if (const auto term = value.optional(role)) lobe.terms.push_back({role, parseRgbSpellings(*term)});
    if (lobe.terms.empty()) value.fail("expected \"direct\" and/or \"indirect\" light passes");
    return lobe;
}

}  // namespace

BeautyModel parseBeautyModel(const JsonField& section) {
    section.requireObject("{\"channels\": ..., \"light\": ..., \"lobes\": [...]}");
    section.checkKeys({"channels", "light", "lobes", "added", "comment"});
    BeautyModel model;
    model.beauty = parseRgbSpellings(section.required("channels", "the beauty's RGB"));
    if (const auto light = section.optional("light")) model.divided = light->choice({"divided", "multiplied"}) == 0;
    const JsonField lobes = section.required("lobes");
    lobes.requireArray("an array of lobes");
    int albedo_lobes = 0;
    for (const JsonField& lobe : lobes.elements()) {
        model.lobes.push_back(parseLobe(lobe));
        if (model.lobes.back().follows_albedo && ++albedo_lobes > 1)
            lobe.fail("only one lobe may have the albedo as its colour");
    }
    if (const auto added = section.optional("added")) {
        added->requireObject("an object of pass name -> channel patterns");
        for (const auto& [name, spellings] : added->members())
            if (!JsonField::isNoteKey(name) && name != "comment") model.added.push_back({name, parseRgbSpellings(spellings)});
    }
    return model;
}

}  // namespace decalcomp
