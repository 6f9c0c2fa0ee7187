#include "scene/material_json.hpp"

#include <fmt/format.h>

#include <cmath>

#include "decalcomp/error.hpp"

namespace decalcomp::scene_detail {

namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& what) {
    throw inputError(fmt::format("{}: {}: {}", file, path, what));
}

constexpr double kMaxFactor = 1e6;

float factorOf(const json& v, const std::string& file, const std::string& path) {
    if (!v.is_number() || !(v.get<double>() >= 0.0 && v.get<double>() <= kMaxFactor))
        fail(file, path, "expected a factor >= 0 (0 leaves the attribute alone, 1 is full strength)");
    return float(v.get<double>());
}

BlendOp opOf(const json& v, const std::string& file, const std::string& path) {
    const std::string name = v.is_string() ? v.get<std::string>() : std::string();
    for (BlendOp op : {BlendOp::Over, BlendOp::Multiply, BlendOp::Add, BlendOp::Replace})
        if (name == blendOpName(op)) return op;
    fail(file, path, "expected one of: over, multiply, add, replace");
}

NormalBlend normalBlendOf(const json& v, const std::string& file, const std::string& path) {
    const std::string name = v.is_string() ? v.get<std::string>() : std::string();
    for (NormalBlend b : {NormalBlend::Reoriented, NormalBlend::Udn, NormalBlend::Whiteout, NormalBlend::Replace})
        if (name == normalBlendName(b)) return b;
    fail(file, path, "expected one of: rnm, udn, whiteout, replace");
}

bool isColourTarget(DecalTarget t) { return t == DecalTarget::Albedo || t == DecalTarget::Emission; }

// Albedo and emission take [r, g, b] or one number for grey; the scalars one number in [0, 1].
glm::vec3 valueOf(const json& v, DecalTarget target, const std::string& file, const std::string& path) {
    auto finite = [&](const json& x, const std::string& at) {
        if (!x.is_number() || !std::isfinite(x.get<double>())) fail(file, at, "expected a finite number");
        return float(x.get<double>());
    };
    if (isColourTarget(target)) {
        if (v.is_number()) return glm::vec3(finite(v, path));
        if (!v.is_array() || v.size() != 3) fail(file, path, "expected [r, g, b] (linear) or one number");
        return {finite(v[0], path + "[0]"), finite(v[1], path + "[1]"), finite(v[2], path + "[2]")};
    }
    const float x = finite(v, path);
    if (!(x >= 0.0f && x <= 1.0f)) fail(file, path, "expected a number in [0, 1]");
    return glm::vec3(x);
}

void parseTarget(const json& v, DecalTarget target, const std::string& path, const std::string& file, Decal& out) {
    TargetEffect& e = out.effect(target);
    e.factor = 1.0f;  // listed: full strength unless the object says otherwise
    if (v.is_number()) {
        e.factor = factorOf(v, file, path);
        return;
    }
    if (!v.is_object()) fail(file, path, "expected a factor or an object with factor, op, value");
    const bool normal = target == DecalTarget::Normal;
    for (const auto& [key, value] : v.items()) {
        const std::string at = path + "." + key;
        if (key == "factor") {
            e.factor = factorOf(value, file, at);
        } else if (key == "op" && !normal) {
            e.op = opOf(value, file, at);
        } else if (key == "value" && !normal) {
            e.value = valueOf(value, target, file, at);
        } else if (key == "mode" && normal) {
            out.normal_blend = normalBlendOf(value, file, at);
        } else if (key == "strength" && normal) {
            if (!value.is_number() || !(value.get<double>() >= 0.0 && value.get<double>() <= 100.0))
                fail(file, at, "expected a number in [0, 100] (1 = the map as painted)");
            out.normal_strength = float(value.get<double>());
        } else if (key.empty() || key[0] != '_') {
            fail(file, at, normal ? "unknown key (normal takes factor, mode, strength)" : "unknown key (supported: factor, op, value)");
        }
    }
}

}  // namespace

void parseAffects(const json& affects, const std::string& path, const std::string& file, Decal& out) {
    if (!affects.is_object()) fail(file, path, "expected an object like {\"albedo\": 1, \"roughness\": 0.5}");
    for (TargetEffect& e : out.effects) e.factor = 0.0f;  // only what is listed
    for (const auto& [key, value] : affects.items()) {
        if (!key.empty() && key[0] == '_') continue;
        bool known = false;
        for (int t = 0; t < kDecalTargets; ++t)
            if (key == decalTargetName(DecalTarget(t))) {
                parseTarget(value, DecalTarget(t), path + "." + key, file, out);
                known = true;
            }
        if (!known) fail(file, path + "." + key, "unknown attribute (supported: albedo, normal, roughness, metallic, ao, emission)");
    }
}

}  // namespace decalcomp::scene_detail
