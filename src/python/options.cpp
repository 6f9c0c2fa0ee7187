// Keyword arguments -> the library's option structs, worded as the CLI's flags are.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "bindings.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp::python {

namespace {

Error usage(const std::string& message) { return Error(ErrorKind::Usage, message); }

Attribute attributeNamed(const std::string& name, const char* argument) {
    const auto attribute = attributeFromName(name);
    if (!attribute) throw usage(fmt::format("{}: unknown attribute '{}'", argument, name));
    return *attribute;
}

// ["a.R", "a.G"] or "a.R,a.G"
std::vector<std::string> channelList(const py::handle& value) {
    if (py::isinstance<py::str>(value)) {
        std::vector<std::string> names;
        const std::string text = value.cast<std::string>();
        for (std::size_t start = 0;;) {
            const auto comma = text.find(',', start);
            names.push_back(text.substr(start, comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        return names;
    }
    return value.cast<std::vector<std::string>>();
}

}  // namespace

py::object argument(const py::kwargs& kwargs, const char* key) {
    return kwargs.contains(key) && !kwargs[key].is_none() ? py::reinterpret_borrow<py::object>(kwargs[key])
                                                          : py::object();
}

DepthConvention depthArgument(const std::string& value) {
    const auto convention = depthConventionFromName(value);
    if (!convention) throw usage(fmt::format("depth={}: expected planar, radial, ndc or position", value));
    return *convention;
}

NormalsArgument normalsArgument(const std::string& value) {
    const auto comma = value.find(',');
    const std::string space = value.substr(0, comma);
    const auto wrong = [&] { return usage(fmt::format("normals={}: expected world|camera[,signed|packed]", value)); };
    if (space != "world" && space != "camera") throw wrong();
    NormalsArgument normals;
    normals.space = space == "camera" ? NormalSpace::Camera : NormalSpace::World;
    if (comma != std::string::npos) {
        const std::string encoding = value.substr(comma + 1);
        if (encoding != "signed" && encoding != "packed" && encoding != "unsigned") throw wrong();
        normals.packed = encoding != "signed";  // packed, or its alias unsigned (as the CLI)
    }
    return normals;
}

bool uvOriginTopArgument(const std::string& value) {
    if (value != "bottom" && value != "top") throw usage(fmt::format("uv_origin={}: expected bottom or top", value));
    return value == "top";
}

MappingOptions mappingOptions(const py::kwargs& kwargs) {
    MappingOptions options;
    auto get = [&](const char* key) { return argument(kwargs, key); };
    if (auto v = get("profile")) options.profile = v.cast<std::string>();
    if (auto v = get("profile_files")) options.profile_files = v.cast<std::vector<std::string>>();
    if (auto v = get("layer")) options.layer = v.cast<std::string>();
    if (auto v = get("depth")) options.depth_convention = depthArgument(v.cast<std::string>());
    if (auto v = get("reversed_z")) options.reversed_z = v.cast<bool>();
    if (auto v = get("normals")) {
        const NormalsArgument normals = normalsArgument(v.cast<std::string>());
        options.normal_space = normals.space;
        if (normals.packed) options.normal_packed = *normals.packed;
    }
    if (auto v = get("channels"))
        for (const auto& [key, value] : v.cast<py::dict>()) {
            const std::string name = key.cast<std::string>();
            const Attribute attribute = attributeNamed(name, "channels");
            std::vector<std::string> names = channelList(value);
            if (int(names.size()) != attributeComponents(attribute))
                throw usage(fmt::format("channels['{}']: {} needs {} channel(s), got {}", name, name,
                                        attributeComponents(attribute), names.size()));
            options.explicit_channels[attribute] = std::move(names);
        }
    if (auto v = get("add_channels"))
        for (const auto& [key, value] : v.cast<py::dict>()) {
            const std::string name = key.cast<std::string>();
            const Attribute attribute = attributeNamed(name, "add_channels");
            if (attribute != Attribute::Roughness && attribute != Attribute::Metallic &&
                attribute != Attribute::AmbientOcclusion && attribute != Attribute::Emission)
                throw usage(fmt::format("add_channels['{}']: expected roughness, metallic, ao or emission", name));
            options.add_channels[attribute] = value.is_none() ? addedChannelDefault(attribute) : value.cast<float>();
        }
    return options;
}

std::map<Attribute, std::string> passFiles(const py::object& passes) {
    std::map<Attribute, std::string> files;
    if (passes.is_none()) return files;
    for (const auto& [key, value] : passes.cast<py::dict>())
        files[attributeNamed(key.cast<std::string>(), "passes")] = value.cast<std::string>();
    return files;
}

void rejectUnknown(const py::kwargs& kwargs, std::initializer_list<const char*> known, const char* function) {
    for (const auto& [key, value] : kwargs) {
        const std::string name = key.cast<std::string>();
        if (std::none_of(known.begin(), known.end(), [&](const char* k) { return name == k; }))
            throw py::type_error(fmt::format("{}() got an unexpected keyword argument '{}' (known: {})", function,
                                             name, fmt::join(known, ", ")));
    }
}

}  // namespace decalcomp::python
