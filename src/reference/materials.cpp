// Reference material blending, written from docs/conventions.md "Materials" in double precision.
#include <algorithm>
#include <cmath>

#include "decalcomp/reference.hpp"
#include "reference/decal_hit.hpp"

namespace decalcomp::reference {

std::optional<glm::dvec3> straight(const std::optional<glm::dvec4>& texel) {
    if (!texel || !(texel->a > 0.0)) return std::nullopt;
    return glm::dvec3(*texel) / texel->a;
}

namespace {

// The normal map's detail in the decal's image frame, or nullopt when it is unusable.
std::optional<glm::dvec3> normalDetail(const glm::dvec3& rgb, double strength) {
    glm::dvec3 d = rgb * 2.0 - 1.0;
    d.x *= strength;
    d.y *= strength;
    if (!(glm::length(d) > 1e-6)) return std::nullopt;
    return glm::normalize(d);
}

}  // namespace

Surface surfaceAt(const std::map<Attribute, Plane>& planes, std::size_t i) {
    Surface s;
    auto get = [&](Attribute a, int c) { return planes.count(a) ? double(planes.at(a).at(i, c)) : 0.0; };
    for (int c = 0; c < 3; ++c) {
        s.albedo[c] = get(Attribute::Albedo, c);
        s.emission[c] = get(Attribute::Emission, c);
    }
    s.roughness = get(Attribute::Roughness, 0);
    s.metallic = get(Attribute::Metallic, 0);
    s.ao = get(Attribute::AmbientOcclusion, 0);
    return s;
}

void addWeighted(Surface& sum, const Surface& s, double w) {
    sum.albedo += w * s.albedo;
    sum.normal += w * s.normal;
    sum.emission += w * s.emission;
    sum.roughness += w * s.roughness;
    sum.metallic += w * s.metallic;
    sum.ao += w * s.ao;
    sum.normal_changed = sum.normal_changed || s.normal_changed;
}

void storeSurface(const Surface& s, std::size_t i, std::map<Attribute, Plane>& planes) {
    auto set = [&](Attribute a, int c, double v) {
        if (planes.count(a)) planes.at(a).at(i, c) = float(v);
    };
    for (int c = 0; c < 3; ++c) {
        set(Attribute::Albedo, c, s.albedo[c]);
        set(Attribute::Emission, c, s.emission[c]);
    }
    set(Attribute::Roughness, 0, s.roughness);
    set(Attribute::Metallic, 0, s.metallic);
    set(Attribute::AmbientOcclusion, 0, s.ao);
}

glm::dvec3 blend(const glm::dvec3& a, const glm::dvec3& v, double g, BlendOp op) {
    const double f = std::clamp(g, 0.0, 1.0);
    switch (op) {
        case BlendOp::Over: return glm::mix(a, v, f);
        case BlendOp::Multiply: return a * glm::mix(glm::dvec3(1.0), v, f);
        case BlendOp::Add: return a + v * g;
        case BlendOp::Replace: return g > 0.0 ? v : a;
    }
    return a;
}

double blend(double a, double v, double g, BlendOp op) { return blend(glm::dvec3(a), glm::dvec3(v), g, op).x; }

glm::dvec3 combineNormals(const glm::dvec3& b, const glm::dvec3& d, NormalBlend mode) {
    switch (mode) {
        case NormalBlend::Udn: return glm::normalize(glm::dvec3(b.x + d.x, b.y + d.y, b.z));
        case NormalBlend::Whiteout: return glm::normalize(glm::dvec3(b.x + d.x, b.y + d.y, b.z * d.z));
        case NormalBlend::Replace: return d;
        case NormalBlend::Reoriented: {
            // Rotate the detail by the rotation that takes +Z to the base (Barré-Brisebois and Hill).
            const glm::dvec3 z(0.0, 0.0, 1.0);
            if (!(b.z > -1.0 + 1e-6)) return d;
            const glm::dvec3 axis = glm::cross(z, b);
            const double c = b.z;  // cos of the angle between +Z and b
            // Rodrigues with k = axis / |axis|, sin = |axis|: v cos + (k x v) sin + k (k.v)(1 - cos)
            return glm::normalize(d * c + glm::cross(axis, d) + axis * glm::dot(axis, d) / (1.0 + c));
        }
    }
    return d;
}

bool applyDecal(const Decal& decal, const DecalValues& v, double strength, const glm::dvec3& surface_normal,
                const std::function<bool(DecalTarget)>& has, Surface& s) {
    // coverage: the albedo's alpha, else the first texture of the set's, else full
    double coverage = 1.0;
    for (const auto* texel : {&v.albedo, &v.normal, &v.orm, &v.emission})
        if (texel->has_value()) {
            coverage = (*texel)->a;
            break;
        }
    const double g = coverage * strength;
    if (!(g > 0.0)) return false;
    auto wants = [&](DecalTarget t) { return has(t) && decalAffects(decal, t); };
    auto gain = [&](DecalTarget t) { return g * double(decal.effect(t).factor); };
    bool changed = false;
    // a constant wins over the texture (which then only shapes the coverage)
    auto colourOf = [&](const std::optional<glm::dvec4>& texel, DecalTarget t) -> std::optional<glm::dvec3> {
        if (decal.effect(t).value) return glm::dvec3(*decal.effect(t).value);
        return straight(texel);
    };
    if (wants(DecalTarget::Albedo))
        if (const auto value = colourOf(v.albedo, DecalTarget::Albedo)) {
            s.albedo = blend(s.albedo, *value, gain(DecalTarget::Albedo), decal.effect(DecalTarget::Albedo).op);
            changed = true;
        }
    if (wants(DecalTarget::Normal))
        if (const auto rgb = straight(v.normal))
            if (const auto detail = normalDetail(*rgb, decal.normal_strength)) {
                const glm::dvec3 n = decal.normal_blend == NormalBlend::Replace ? v.facing : surface_normal;
                const glm::dvec3 t_raw = v.right - n * glm::dot(n, v.right);
                if (glm::length(t_raw) > 1e-2 * glm::length(v.right)) {
                    const glm::dvec3 t = glm::normalize(t_raw);
                    const glm::dvec3 b_raw = v.up - n * glm::dot(n, v.up) - t * glm::dot(t, v.up);
                    if (glm::length(b_raw) > 1e-2 * glm::length(v.up)) {
                        const glm::dvec3 b = glm::normalize(b_raw);
                        const glm::dvec3 base(glm::dot(s.normal, t), glm::dot(s.normal, b), glm::dot(s.normal, n));
                        const glm::dvec3 r = combineNormals(base, *detail, decal.normal_blend);
                        const glm::dvec3 mapped = t * r.x + b * r.y + n * r.z;
                        const glm::dvec3 mixed = glm::mix(s.normal, mapped, std::clamp(gain(DecalTarget::Normal), 0.0, 1.0));
                        s.normal = glm::length(mixed) > 1e-6 ? glm::normalize(mixed) : mapped;
                        s.normal_changed = changed = true;
                    }
                }
            }
    // occlusion, roughness, metallic: the ORM texture's R, G, B, or the constants
    const auto orm = straight(v.orm);
    const std::pair<DecalTarget, double*> scalars[] = {{DecalTarget::AmbientOcclusion, &s.ao},
                                                       {DecalTarget::Roughness, &s.roughness},
                                                       {DecalTarget::Metallic, &s.metallic}};
    for (int k = 0; k < 3; ++k) {
        const auto [target, slot] = scalars[k];
        if (!wants(target)) continue;
        std::optional<double> value;
        if (decal.effect(target).value) {
            value = double(decal.effect(target).value->r);
        } else if (orm) {
            value = (*orm)[k];
        }
        if (!value) continue;
        *slot = blend(*slot, *value, gain(target), decal.effect(target).op);
        changed = true;
    }
    if (wants(DecalTarget::Emission))
        if (const auto value = colourOf(v.emission, DecalTarget::Emission)) {
            s.emission = blend(s.emission, *value, gain(DecalTarget::Emission), decal.effect(DecalTarget::Emission).op);
            changed = true;
        }
    return changed;
}

}  // namespace decalcomp::reference
