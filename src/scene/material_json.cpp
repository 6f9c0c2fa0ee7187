#include "scene/material_json.hpp"

#include <fmt/format.h>

#include "decalcomp/error.hpp"

namespace decalcomp::scene_detail {

namespace {

constexpr double kMaxFactor = 1e6;

float factorOf(const JsonField& v) {
    const double factor = v.number();
    if (!(factor >= 0.0 && factor <= kMaxFactor))
        v.fail("expected a factor >= 0 (0 leaves the attribute alone, 1 is full strength)");
    return float(factor);
}

bool isColourTarget(DecalTarget t) { return t == DecalTarget::Albedo || t == DecalTarget::Emission; }

// Albedo and emission take [r, g, b] or one number for grey; the scalars one number in [0, 1].
glm::vec3 valueOf(const JsonField& v, DecalTarget target) {
    if (isColourTarget(target)) return glm::vec3(v.vec3OrScalar("[r, g, b] (linear) or one number"));
    return glm::vec3(float(v.numberIn(0.0, 1.0)));
}

void parseTarget(const JsonField& v, DecalTarget target, Decal& out) {
    TargetEffect& e = out.effect(target);
    e.factor = 1.0f;  // listed: full strength unless the object says otherwise
    if (v.value().is_number()) {
        e.factor = factorOf(v);
        return;
    }
    v.requireObject("a factor or an object with factor, op, value");
    if (const auto factor = v.optional("factor")) e.factor = factorOf(*factor);
    if (target == DecalTarget::Normal) {
        v.checkKeys({"factor", "mode", "strength"});
        if (const auto mode = v.optional("mode"))
            out.normal_blend = mode->choice(std::array{NormalBlend::Reoriented, NormalBlend::Udn, NormalBlend::Whiteout,
                                                       NormalBlend::Replace},
                                            normalBlendName);
        if (const auto strength = v.optional("strength")) out.normal_strength = float(strength->numberIn(0.0, 100.0));
        return;
    }
    v.checkKeys({"factor", "op", "value"});
    if (const auto op = v.optional("op"))
        e.op = op->choice(std::array{BlendOp::Over, BlendOp::Multiply, BlendOp::Add, BlendOp::Replace}, blendOpName);
    if (const auto value = v.optional("value")) e.value = valueOf(*value, target);
}

}  // namespace

void parseAffects(const JsonField& affects, Decal& out) {
    affects.requireObject("an object like {\"albedo\": 1, \"roughness\": 0.5}");
    std::vector<std::string> targets;
    for (int t = 0; t < kDecalTargets; ++t) targets.push_back(decalTargetName(DecalTarget(t)));
    affects.checkKeys(targets);
    for (TargetEffect& e : out.effects) e.factor = 0.0f;  // only what is listed
    for (int t = 0; t < kDecalTargets; ++t)
        if (const auto target = affects.optional(targets[std::size_t(t)])) parseTarget(*target, DecalTarget(t), out);
}

}  // namespace decalcomp::scene_detail
