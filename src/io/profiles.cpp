// Renderer profiles as data: JSON parsing and validation, the embedded built-ins, user files.
#include "decalcomp/profiles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>

#include "decalcomp/error.hpp"

namespace decalcomp {

namespace embedded {
extern const std::vector<std::pair<std::string_view, std::string_view>> kProfileFiles;
}

namespace {

using nlohmann::json;

// Where a value sits in the document, for messages: "attributes.albedo[1]".
std::string child(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
std::string child(const std::string& path, std::size_t index) { return fmt::format("{}[{}]", path, index); }

[[noreturn]] void fail(const std::string& source, const std::string& path, const std::string& what) {
    throw inputError(path.empty() ? fmt::format("{}: {}", source, what) : fmt::format("{}: {}: {}", source, path, what));
}

std::string requireString(const json& value, const std::string& source, const std::string& path) {
    if (!value.is_string()) fail(source, path, "expected a string");
    return value.get<std::string>();
}

bool isCommentKey(const std::string& key) { return key == "comment" || (!key.empty() && key[0] == '_'); }

// Splits "a.{R,G,B}" into its component names; "{layer}" stays a placeholder.
std::vector<std::string> expandOrFail(const std::string& pattern, const std::string& source, const std::string& path) {
    std::size_t group_open = std::string::npos, group_close = std::string::npos;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '{') continue;
        const std::size_t close = pattern.find('}', i);
        if (close == std::string::npos) fail(source, path, fmt::format("'{}': unmatched '{{'", pattern));
        const std::string inner = pattern.substr(i + 1, close - i - 1);
        if (inner == "layer") {
            if (pattern.find("{layer}", close) != std::string::npos)
                fail(source, path, fmt::format("'{}': {{layer}} may appear once", pattern));
            i = close;
            continue;
        }
        if (inner.find(',') == std::string::npos)
            fail(source, path, fmt::format("'{}': unknown placeholder '{{{}}}' (expected {{layer}} or a component "
                                           "group like {{R,G,B}})",
                                           pattern, inner));
        if (group_open != std::string::npos)
            fail(source, path, fmt::format("'{}': more than one component group", pattern));
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
        if (part.empty()) fail(source, path, fmt::format("'{}': empty component in the group", pattern));
        names.push_back(head + part + tail);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return names;
}

std::string requireSpace(const json& value, const std::string& source, const std::string& path) {
    const std::string space = requireString(value, source, path);
    if (space != "world" && space != "camera") fail(source, path, fmt::format("'{}': expected world or camera", space));
    return space;
}

ProfileSpelling parseSpelling(const json& value, Attribute attribute, const std::string& source,
                              const std::string& path) {
    ProfileSpelling spelling;
    const json* channels = &value;
    if (value.is_object()) {
        for (const auto& [key, field] : value.items()) {
            if (key == "channels") continue;
            if (key == "space") {
                if (attribute != Attribute::Normal) fail(source, child(path, key), "only normal spellings have a space");
                spelling.space = requireSpace(field, source, child(path, key));
            } else if (!isCommentKey(key)) {
                fail(source, child(path, key), "unknown field (expected channels, space)");
            }
        }
        if (!value.contains("channels")) fail(source, child(path, "channels"), "missing");
        channels = &value["channels"];
    }
    const std::string channels_path = value.is_object() ? child(path, "channels") : path;
    if (channels->is_string()) {
        spelling.channels = expandOrFail(channels->get<std::string>(), source, channels_path);
    } else if (channels->is_array()) {
        for (std::size_t i = 0; i < channels->size(); ++i) {
            const std::string name = requireString((*channels)[i], source, child(channels_path, i));
            const std::vector<std::string> expanded = expandOrFail(name, source, child(channels_path, i));
            if (expanded.size() != 1)
                fail(source, child(channels_path, i), "a component group belongs in a single-pattern spelling");
            spelling.channels.push_back(name);
        }
    } else {
        fail(source, channels_path, "expected a channel pattern or an array of them");
    }
    const int components = attributeComponents(attribute);
    if (int(spelling.channels.size()) != components)
        fail(source, channels_path, fmt::format("expected {} channel pattern(s), got {}", components,
                                                spelling.channels.size()));
    for (const std::string& name : spelling.channels)
        if (name.empty()) fail(source, channels_path, "empty channel pattern");
    return spelling;
}

ProfileDetectRule parseDetectRule(const json& value, const std::string& source, const std::string& path) {
    if (!value.is_object()) fail(source, path, "expected an object with \"header\" or \"channel\"");
    ProfileDetectRule rule;
    for (const auto& [key, field] : value.items()) {
        if (key == "header") rule.header = requireString(field, source, child(path, key));
        else if (key == "value") rule.value = requireString(field, source, child(path, key));
        else if (key == "channel") rule.channel = requireString(field, source, child(path, key));
        else if (key == "weight") {
            if (!field.is_number() || !(field.get<double>() >= 0.0) || !(field.get<double>() <= 100.0))
                fail(source, child(path, key), "expected a number in [0, 100]");
            rule.weight = field.get<double>();
        } else if (!isCommentKey(key)) {
            fail(source, child(path, key), "unknown field (expected header, value, channel, weight)");
        }
    }
    if (rule.header.empty() == rule.channel.empty()) fail(source, path, "expected exactly one of \"header\" and \"channel\"");
    if (!rule.value.empty() && rule.header.empty()) fail(source, child(path, "value"), "only header rules have a value");
    return rule;
}

ChannelProfile parseProfileJson(const json& doc, const std::string& source, const std::string& path) {
    if (!doc.is_object()) fail(source, path, "expected a profile object");
    ChannelProfile profile;
    profile.source = source;
    for (const auto& [key, value] : doc.items()) {
        const std::string at = child(path, key);
        if (key == "name") {
            profile.name = requireString(value, source, at);
            if (profile.name.empty() || profile.name == "auto")
                fail(source, at, "a profile needs a name other than \"auto\"");
            for (char c : profile.name)
                if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.'))
                    fail(source, at, fmt::format("'{}': use letters, digits, '-', '_' and '.'", profile.name));
        } else if (key == "description") {
            profile.description = requireString(value, source, at);
        } else if (key == "detect") {
            if (!value.is_array()) fail(source, at, "expected an array of rules");
            for (std::size_t i = 0; i < value.size(); ++i)
                profile.detect.push_back(parseDetectRule(value[i], source, child(at, i)));
        } else if (key == "depth_convention") {
            const auto convention = depthConventionFromName(requireString(value, source, at));
            if (!convention) fail(source, at, "expected planar, radial, ndc or position");
            profile.depth_convention = *convention;
        } else if (key == "normal") {
            if (!value.is_object()) fail(source, at, "expected {\"space\": ..., \"encoding\": ...}");
            for (const auto& [nkey, nvalue] : value.items()) {
                if (nkey == "space") profile.normal_space = requireSpace(nvalue, source, child(at, nkey));
                else if (nkey == "encoding") {
                    profile.normal_encoding = requireString(nvalue, source, child(at, nkey));
                    if (profile.normal_encoding != "signed" && profile.normal_encoding != "unsigned")
                        fail(source, child(at, nkey), "expected signed or unsigned");
                } else if (!isCommentKey(nkey)) {
                    fail(source, child(at, nkey), "unknown field (expected space, encoding)");
                }
            }
        } else if (key == "attributes") {
            if (!value.is_object()) fail(source, at, "expected an object keyed by attribute");
            for (const auto& [name, spellings] : value.items()) {
                const auto attribute = attributeFromName(name);
                if (!attribute)
                    fail(source, child(at, name),
                         "unknown attribute (expected depth, albedo, normal, position, object_id, uv, roughness, metallic)");
                if (!spellings.is_array() || spellings.empty())
                    fail(source, child(at, name), "expected a non-empty array of spellings");
                auto& list = profile.attributes[*attribute];
                for (std::size_t i = 0; i < spellings.size(); ++i)
                    list.push_back(parseSpelling(spellings[i], *attribute, source, child(child(at, name), i)));
            }
        } else if (!isCommentKey(key)) {
            fail(source, at,
                 "unknown field (expected name, description, detect, depth_convention, normal, attributes)");
        }
    }
    if (profile.name.empty()) fail(source, child(path, "name"), "missing");
    if (profile.attributes.empty()) fail(source, child(path, "attributes"), "missing or empty");
    return profile;
}

json parseText(const std::string& text, const std::string& source) {
    try {
        return json::parse(text);
    } catch (const json::parse_error& e) {
        throw inputError(fmt::format("{}: not valid JSON (byte {})", source, e.byte));
    }
}

std::vector<ChannelProfile> parseProfileDocument(const std::string& text, const std::string& source) {
    const json doc = parseText(text, source);
    std::vector<ChannelProfile> profiles;
    if (doc.is_array()) {
        for (std::size_t i = 0; i < doc.size(); ++i)
            profiles.push_back(parseProfileJson(doc[i], source, fmt::format("[{}]", i)));
    } else if (doc.is_object() && doc.contains("profiles")) {
        const json& list = doc["profiles"];
        if (!list.is_array()) fail(source, "profiles", "expected an array of profiles");
        for (std::size_t i = 0; i < list.size(); ++i)
            profiles.push_back(parseProfileJson(list[i], source, child("profiles", i)));
    } else {
        profiles.push_back(parseProfileJson(doc, source, ""));
    }
    if (profiles.empty()) fail(source, "", "no profiles");
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
    return expandOrFail(pattern, "pattern", "");
}

ChannelProfile parseProfile(const std::string& json_text, const std::string& source) {
    return parseProfileJson(parseText(json_text, source), source, "");
}

const std::vector<ChannelProfile>& builtinProfiles() {
    static const std::vector<ChannelProfile> profiles = [] {
        std::vector<ChannelProfile> all;
        for (const auto& [file, text] : embedded::kProfileFiles)
            for (ChannelProfile& p : parseProfileDocument(std::string(text), "built-in profile " + std::string(file))) {
                p.source = "built-in";
                all.push_back(std::move(p));
            }
        // Tie-break order: the neutral generic names first, then the renderers.
        const std::vector<std::string> order = {"generic", "blender", "arnold", "renderman", "unreal"};
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
    std::ifstream in(path);
    if (!in) throw inputError(fmt::format("{}: cannot open profile file", path));
    std::stringstream text;
    text << in.rdbuf();
    return parseProfileDocument(text.str(), path);
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
