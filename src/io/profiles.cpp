// Renderer profiles as data: JSON parsing and validation, the embedded built-ins, user files.
#include "decalcomp/profiles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <string_view>

#include "decalcomp/error.hpp"
#include "decalcomp/json_fields.hpp"
#include "profile_beauty.hpp"

namespace decalcomp {

namespace embedded {
extern const std::vector<std::pair<std::string_view, std::string_view>> kProfileFiles;
}

namespace {

using nlohmann::json;

// "comment" is a note in profile files, beside the '_' keys every format ignores.
std::vector<std::string> withComment(std::vector<std::string> keys) {
    keys.push_back("comment");
    return keys;
}

// Splits "a.{R,G,B}" into its component names; "{layer}" stays a placeholder.
std::vector<std::string> expandOrFail(const std::string& pattern, const JsonField& at) {
    std::size_t group_open = std::string::npos, group_close = std::string::npos;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '{') continue;
        const std::size_t close = pattern.find('}', i);
        if (close == std::string::npos) at.fail(fmt::format("'{}': unmatched '{{'", pattern));
        const std::string inner = pattern.substr(i + 1, close - i - 1);
        if (inner == "layer") {
            if (pattern.find("{layer}", close) != std::string::npos)
                at.fail(fmt::format("'{}': {{layer}} may appear once", pattern));
            i = close;
            continue;
        }
        if (inner.find(',') == std::string::npos)
            at.fail(fmt::format("'{}': unknown placeholder '{{{}}}' (expected {{layer}} or a component "
                                "group like {{R,G,B}})",
                                pattern, inner));
        if (group_open != std::string::npos) at.fail(fmt::format("'{}': more than one component group", pattern));
        group_open = i;
        group_close = close;
        i = close;
    }
    if (group_open == std::string::npos) return {pattern};
    std::vector<std::string> names;
    const std::string head = pattern.substr(0, group_open), tail = pattern.substr(group_close + 1);
    const std::string inner = pattern.substr(group_open + 1, group_close - group_open - 1);
    for (std::size_t start = 0;;) {
        const std::size_t comma = inner.find(',', start);
        const std::string part = inner.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (part.empty()) at.fail(fmt::format("'{}': empty component in the group", pattern));
        names.push_back(head + part + tail);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return names;
}

std::string spaceOf(const JsonField& value) { return value.choice({"world", "camera"}) == 0 ? "world" : "camera"; }

ProfileSpelling parseSpelling(const JsonField& value, Attribute attribute) {
    ProfileSpelling spelling;
    std::optional<JsonField> object_channels;
    if (value.isObject()) {
        value.checkKeys(withComment({"channels", "space"}));
        if (const auto space = value.optional("space")) {
            if (attribute != Attribute::Normal) space->fail("only normal spellings have a space");
            spelling.space = spaceOf(*space);
        }
        object_channels = value.required("channels");
    }
    const JsonField channels = object_channels ? *object_channels : value;
    if (channels.value().is_string()) {
        spelling.channels = expandOrFail(channels.string(), channels);
    } else if (channels.isArray()) {
        for (const JsonField& pattern : channels.elements()) {
            const std::string name = pattern.string();
            if (expandOrFail(name, pattern).size() != 1)
                pattern.fail("a component group belongs in a single-pattern spelling");
            spelling.channels.push_back(name);
        }
    } else {
        channels.fail("expected a channel pattern or an array of them");
    }
    const int components = attributeComponents(attribute);
    if (int(spelling.channels.size()) != components)
        channels.fail(fmt::format("expected {} channel pattern(s), got {}", components, spelling.channels.size()));
    for (const std::string& name : spelling.channels)
        if (name.empty()) channels.fail("empty channel pattern");
    return spelling;
}

ProfileDetectRule parseDetectRule(const JsonField& value) {
    value.requireObject("an object with \"header\" or \"channel\"");
    value.checkKeys(withComment({"header", "value", "channel", "weight"}));
    ProfileDetectRule rule;
    rule.header = value.optionalString("header").value_or("");
    rule.value = value.optionalString("value").value_or("");
    rule.channel = value.optionalString("channel").value_or("");
    if (const auto weight = value.optional("weight")) rule.weight = weight->numberIn(0.0, 100.0);
    if (rule.header.empty() == rule.channel.empty()) value.fail("expected exactly one of \"header\" and \"channel\"");
    if (!rule.value.empty() && rule.header.empty()) value.required("value").fail("only header rules have a value");
    return rule;
}

std::vector<std::string> attributeNames() {
    std::vector<std::string> names;
    for (Attribute a : kAllAttributes) names.push_back(attributeName(a));
    return names;
}

ChannelProfile parseProfileJson(const JsonField& doc) {
    doc.requireObject("a profile object");
    doc.checkKeys(withComment({"name", "description", "detect", "depth_convention", "normal", "attributes", "beauty", "pixel_filter"}));
    ChannelProfile profile;
    profile.source = doc.file();
    const JsonField name = doc.required("name");
    profile.name = name.string();
    if (profile.name.empty() || profile.name == "auto") name.fail("a profile needs a name other than \"auto\"");
    for (char c : profile.name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.'))
            name.fail(fmt::format("'{}': use letters, digits, '-', '_' and '.'", profile.name));
    profile.description = doc.optionalString("description").value_or("");
    if (const auto detect = doc.optional("detect")) {
        detect->requireArray("an array of rules");
        for (const JsonField& rule : detect->elements()) profile.detect.push_back(parseDetectRule(rule));
    }
    if (const auto convention = doc.optional("depth_convention"))
        profile.depth_convention = convention->choice(
            std::array{DepthConvention::Planar, DepthConvention::Radial, DepthConvention::Ndc, DepthConvention::Position},
            depthConventionName);
    if (const auto normal = doc.optional("normal")) {
        normal->requireObject("{\"space\": ..., \"encoding\": ...}");
        normal->checkKeys(withComment({"space", "encoding"}));
        if (const auto space = normal->optional("space")) profile.normal_space = spaceOf(*space);
        if (const auto encoding = normal->optional("encoding"))
            // The CLI's words (--normals SPACE,signed|packed); "unsigned" is the older spelling of packed.
            profile.normal_encoding = encoding->choice({"signed", "packed", "unsigned"}) == 0 ? "signed" : "packed";
    }
    const JsonField attributes = doc.required("attributes");
    attributes.requireObject("an object keyed by attribute");
    attributes.checkKeys(attributeNames());
    for (const auto& [key, spellings] : attributes.members()) {
        if (JsonField::isNoteKey(key)) continue;
        const Attribute attribute = *attributeFromName(key);
        spellings.requireArray("a non-empty array of spellings");
        if (spellings.size() == 0) spellings.fail("expected a non-empty array of spellings");
        for (const JsonField& spelling : spellings.elements())
            profile.attributes[attribute].push_back(parseSpelling(spelling, attribute));
    }
    if (profile.attributes.empty()) attributes.fail("expected at least one attribute");
    if (const auto beauty = doc.optional("beauty")) profile.beauty = parseBeautyModel(*beauty);
    if (const auto filter = doc.optional("pixel_filter")) {
        try {
            profile.pixel_filter = parsePixelFilter(filter->string(), "");
        } catch (const Error& e) {
            filter->fail(e.what());
        }
    }
    return profile;
}

std::vector<ChannelProfile> parseProfileDocument(const json& doc, const std::string& source) {
    const JsonField root(doc, source);
    std::vector<ChannelProfile> profiles;
    if (root.isArray()) {
        for (const JsonField& entry : root.elements()) profiles.push_back(parseProfileJson(entry));
    } else if (root.has("profiles")) {
        const JsonField list = root.required("profiles");
        list.requireArray("an array of profiles");
        for (const JsonField& entry : list.elements()) profiles.push_back(parseProfileJson(entry));
    } else {
        profiles.push_back(parseProfileJson(root));
    }
    if (profiles.empty()) root.fail("no profiles");
    return profiles;
}

void addReplacing(std::vector<ChannelProfile>& set, ChannelProfile profile) {
    for (ChannelProfile& existing : set)
        if (existing.name == profile.name) {
            existing = std::move(profile);
            return;
        }
    set.push_back(std::move(profile));
}

}  // namespace

double attributeDetectionWeight(Attribute attribute) {
    switch (attribute) {
        case Attribute::Depth:
        case Attribute::Albedo: return 4.0;
        case Attribute::Position:
        case Attribute::Normal: return 2.0;
        default: return 1.0;
    }
}

std::vector<std::string> expandChannelPattern(const std::string& pattern) {
    const json value = pattern;
    return expandOrFail(pattern, JsonField(value, "pattern"));
}

ChannelProfile parseProfile(const std::string& json_text, const std::string& source) {
    const json doc = parseJsonText(json_text, source);
    return parseProfileJson(JsonField(doc, source));
}

const std::vector<ChannelProfile>& builtinProfiles() {
    static const std::vector<ChannelProfile> profiles = [] {
        std::vector<ChannelProfile> all;
        for (const auto& [file, text] : embedded::kProfileFiles) {
            const std::string source = "built-in profile " + std::string(file);
            for (ChannelProfile& p : parseProfileDocument(parseJsonText(std::string(text), source), source)) {
                p.source = "built-in";
                all.push_back(std::move(p));
            }
        }
        // Tie-break order: the neutral generic names first, then the renderers.
        const std::vector<std::string> order = {"generic", "blender", "arnold", "renderman", "unreal", "vray"};
        auto rank = [&](const ChannelProfile& p) {
            for (std::size_t i = 0; i < order.size(); ++i)
                if (order[i] == p.name) return i;
            return order.size();
        };
        std::stable_sort(all.begin(), all.end(),
                         [&](const ChannelProfile& a, const ChannelProfile& b) { return rank(a) < rank(b); });
        return all;
    }();
    return profiles;
}

std::vector<ChannelProfile> loadProfileFile(const std::string& path) {
    return parseProfileDocument(readJsonFile(path, "profile file"), path);
}

std::vector<ChannelProfile> profileSet(const std::vector<std::string>& files) {
    std::vector<ChannelProfile> user;
    for (const std::string& file : files)
        for (ChannelProfile& p : loadProfileFile(file)) addReplacing(user, std::move(p));
    std::vector<ChannelProfile> set = user;
    for (const ChannelProfile& builtin : builtinProfiles()) {
        bool replaced = false;
        for (const ChannelProfile& p : user) replaced = replaced || p.name == builtin.name;
        if (!replaced) set.push_back(builtin);
    }
    return set;
}

}  // namespace decalcomp
