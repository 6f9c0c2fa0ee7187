// The reference bake (reference_bake.hpp), written from docs/texture-space.md "Bake mode": per
// texel every triangle of the mesh is tested (no grid), in double. The apron comes from the
// library's uvApron (host code the kernel is given, not kernel math: the test checks the kernel).
#include "decalcomp/reference_bake.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "decalcomp/bake.hpp"
#include "reference/decal_hit.hpp"

namespace decalcomp::reference {

namespace {

// Float rounding of the kernel's UV arithmetic (coordinates below 1, float epsilon 1.2e-7, a few
// operations each): tests within this of deciding count as ambiguous. Barycentric ties get the
// same in weight units times the ratio of a texel to a small face (measured faces >= 1/100 UV).
constexpr double kUvRounding = 4e-6;
constexpr double kWeightRounding = 4e-4;
// Two candidates whose texels differ by less than this give the same bake (float vs double).
constexpr double kSameValue = 1e-5;

glm::dvec4 premultiplied(const glm::dvec3& v, double c) { return glm::dvec4(v * c, c); }

double segmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 e = b - a;
    const double len2 = glm::dot(e, e);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, e) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * e));
}

struct UvTriangle {
    glm::dvec2 a, b, c;
    double det = 0.0;
};
UvTriangle uvTriangle(const RestMesh& m, int t) {
    const glm::ivec3& tri = m.triangles[std::size_t(t)];
    UvTriangle u{glm::dvec2(m.vertices[std::size_t(tri.x)].uv), glm::dvec2(m.vertices[std::size_t(tri.y)].uv),
                 glm::dvec2(m.vertices[std::size_t(tri.z)].uv)};
    const glm::dvec2 e0 = u.b - u.a, e1 = u.c - u.a;
    u.det = e0.x * e1.y - e0.y * e1.x;
    return u;
}

glm::dvec3 weights(const UvTriangle& u, glm::dvec2 p) {
    const glm::dvec2 e0 = u.b - u.a, e1 = u.c - u.a, dp = p - u.a;
    const double wb = (dp.x * e1.y - dp.y * e1.x) / u.det, wc = (e0.x * dp.y - e0.y * dp.x) / u.det;
    return {1.0 - wb - wc, wb, wc};
}

// How far the triangle and the square (centre p, half-size h) overlap along the separating axis
// that separates them best, in UV units: >= 0 iff they meet.
double squareOverlap(const UvTriangle& u, glm::dvec2 p, double h) {
    const glm::dvec2 lo = glm::min(u.a, glm::min(u.b, u.c)), hi = glm::max(u.a, glm::max(u.b, u.c));
    double overlap = std::min({p.x + h - lo.x, hi.x - (p.x - h), p.y + h - lo.y, hi.y - (p.y - h)});
    const glm::dvec2 v[3] = {u.a, u.b, u.c};
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2 s = v[k], e = v[(k + 1) % 3] - s, o = v[(k + 2) % 3] - s;
        glm::dvec2 n(-e.y, e.x);
        if (glm::dot(n, o) < 0.0) n = -n;  // towards the inside
        const double len = glm::length(n);
        overlap = std::min(overlap, (glm::dot(n, p - s) + (std::abs(n.x) + std::abs(n.y)) * h) / len);
    }
    return overlap;
}

// A triangle that may give a texel its rest point, and the rule's order: nearer first, then `tie`.
struct Candidate {
    const RestMesh* mesh = nullptr;
    int triangle = -1;
    glm::dvec3 w{0.0};
    double distance = 0.0, tie = 0.0;
    bool admitted = false;    // meets the texel (touch) or lies within reach (dilation)
    bool borderline = false;  // that decision is within rounding
};
bool better(const Candidate& a, const Candidate& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.tie < b.tie);
}
// Whether float rounding may order the two either way.
bool nearlyTied(const Candidate& a, const Candidate& b) {
    if (std::abs(a.distance - b.distance) > kUvRounding) return false;
    return a.distance > kUvRounding || b.distance > kUvRounding || std::abs(a.tie - b.tie) <= kWeightRounding;
}

Candidate candidate(const RestMesh& m, int t, const UvTriangle& u, glm::dvec2 p, bool apron) {
    Candidate c;
    c.mesh = &m;
    c.triangle = t;
    c.w = weights(u, p);
    const double inside = std::min({c.w.x, c.w.y, c.w.z});
    c.distance = inside >= 0.0 ? 0.0
                               : std::min({segmentDistance(p, u.a, u.b), segmentDistance(p, u.b, u.c),
                                           segmentDistance(p, u.c, u.a)});
    c.tie = apron ? segmentDistance(p, u.a, u.b) : -inside;  // apron: its edge 0-1 is the island border
    return c;
}

glm::dvec3 interpolate(const Candidate& c, const glm::dvec3& w, glm::vec3 RestVertex::*field) {
    const glm::ivec3& tri = c.mesh->triangles[std::size_t(c.triangle)];
    return w.x * glm::dvec3(c.mesh->vertices[std::size_t(tri.x)].*field) +
           w.y * glm::dvec3(c.mesh->vertices[std::size_t(tri.y)].*field) +
           w.z * glm::dvec3(c.mesh->vertices[std::size_t(tri.z)].*field);
}

double largestDifference(const BakedTexel& a, const BakedTexel& b) {
    double d = 0.0;
    for (int k = 0; k < 4; ++k)
        d = std::max({d, std::abs(a.albedo[k] - b.albedo[k]), std::abs(a.orm[k] - b.orm[k]),
                      std::abs(a.emission[k] - b.emission[k])});
    return d;
}

}  // namespace

struct BakeEvaluator::State {
    const DecalScene& scene;
    Decal decal;
    glm::dmat4 world_to_local;
    double scale = 0.0;  // how far rounding moves a local coordinate, per unit of |P|
    double margin = 0.0;
    std::map<int, std::vector<Texture2D>> chains;
};

BakeEvaluator::BakeEvaluator(const DecalScene& scene, const Decal& decal, double margin)
    : state_(new State{scene, decal, glm::inverse(decal.world_matrix), 0.0, margin, {}}) {
    const glm::dmat4& w = state_->world_to_local;
    for (int r = 0; r < 3; ++r)
        state_->scale = std::max(state_->scale, std::abs(w[0][r]) + std::abs(w[1][r]) + std::abs(w[2][r]));
    for (int t : {decal.albedo_texture, decal.normal_texture, decal.orm_texture, decal.emission_texture})
        if (t >= 0 && !state_->chains.count(t)) state_->chains[t] = mipChain(scene.textures.at(std::size_t(t)));
}

BakeEvaluator::~BakeEvaluator() = default;

BakedTexel BakeEvaluator::at(const glm::dvec3& rest, const glm::dvec3& normal, const glm::dvec3& rest_dx,
                             const glm::dvec3& rest_dy) const {
    const State& s = *state_;
    const Decal& d = s.decal;
    const double slack = s.margin * s.scale * (1.0 + glm::length(rest));
    const DecalHit hit = hitDecal(d, s.world_to_local, rest, normal, Footprint{true, rest_dx, rest_dy}, slack);
    BakedTexel out;
    out.ambiguous = hit.ambiguous;
    if (!(hit.fade > 0.0)) return out;
    auto texel = [&](int t) -> std::optional<glm::dvec4> {
        if (t < 0) return std::nullopt;
        return hitTexel(hit, d, s.scene.textures[std::size_t(t)], s.chains.at(t), slack, out.ambiguous);
    };
    const auto albedo = texel(d.albedo_texture), normal_map = texel(d.normal_texture), orm = texel(d.orm_texture),
               emission = texel(d.emission_texture);
    // coverage: the albedo's alpha, else the first texture of the set's, else full
    double coverage = 1.0;
    for (const auto* t : {&albedo, &normal_map, &orm, &emission})
        if (t->has_value()) {
            coverage = (*t)->a;
            break;
        }
    const double c = std::clamp(coverage * hit.fade, 0.0, 1.0);
    if (!(c > 0.0)) return out;
    auto constant = [&](DecalTarget t) { return d.effect(t).value ? std::optional(glm::dvec3(*d.effect(t).value)) : std::nullopt; };
    // a constant wins over the texture; the albedo layer keeps the coverage even without a value
    const auto albedo_value = constant(DecalTarget::Albedo) ? constant(DecalTarget::Albedo) : straight(albedo);
    out.albedo = albedo_value ? premultiplied(*albedo_value, c) : glm::dvec4(0.0, 0.0, 0.0, c);
    // ORM: per channel the constant, else the map's; empty where the map is transparent (exact
    // mode skips the map's channels there; the baked decal applies the constants itself)
    const auto orm_map = straight(orm);
    const DecalTarget orm_targets[3] = {DecalTarget::AmbientOcclusion, DecalTarget::Roughness, DecalTarget::Metallic};
    glm::dvec3 orm_value(0.0);
    bool any_constant = false;
    for (int k = 0; k < 3; ++k) {
        const auto value = constant(orm_targets[k]);
        any_constant = any_constant || value.has_value();
        orm_value[k] = value ? value->r : orm_map ? (*orm_map)[k] : 0.0;
    }
    if (d.orm_texture >= 0 ? orm_map.has_value() : any_constant) out.orm = premultiplied(orm_value, c);
    const auto emission_value = constant(DecalTarget::Emission) ? constant(DecalTarget::Emission) : straight(emission);
    if (emission_value) out.emission = premultiplied(*emission_value, c);
    return out;
}

BakeReference bakeLayers(const DecalScene& scene, const Decal& decal, double margin) {
    const RestMesh& mesh = scene.meshes.at(std::size_t(decal.rest_mesh));
    const RestMesh apron = uvApron(mesh);
    const BakeEvaluator evaluate(scene, decal, margin);
    const int n = decal.bake_resolution;
    const double texel = 1.0 / n, h = 0.5 * texel, reach = std::max(decal.bake_dilation, 0) * texel;
    std::vector<UvTriangle> mesh_uv, apron_uv;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) mesh_uv.push_back(uvTriangle(mesh, int(t)));
    for (std::size_t t = 0; t < apron.triangles.size(); ++t) apron_uv.push_back(uvTriangle(apron, int(t)));

    BakeReference out;
    out.width = out.height = n;
    const std::size_t texels = std::size_t(n) * std::size_t(n);
    out.albedo.assign(texels, glm::dvec4(0.0));
    out.orm = out.emission = out.albedo;
    out.classes.assign(texels, BakeTexelClass::Empty);
    out.ambiguous.assign(texels, 0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::size_t index = std::size_t(j) * std::size_t(n) + std::size_t(i);
            const glm::dvec2 p((i + 0.5) * texel, 1.0 - (j + 0.5) * texel);
            // Candidates in the kernel's order: triangles meeting the texel's square; without one,
            // apron triangles whose border edge is within reach, then mesh triangles within reach.
            // Those within rounding of admission are kept too, marked borderline.
            std::vector<Candidate> touching, near;
            for (std::size_t t = 0; t < mesh_uv.size(); ++t) {
                if (!(std::abs(mesh_uv[t].det) > 0.0)) continue;
                const double overlap = squareOverlap(mesh_uv[t], p, h);
                if (overlap < -kUvRounding) continue;
                Candidate c = candidate(mesh, int(t), mesh_uv[t], p, false);
                c.admitted = overlap >= 0.0;
                c.borderline = std::abs(overlap) <= kUvRounding;
                touching.push_back(c);
            }
            const bool touched = std::any_of(touching.begin(), touching.end(), [](const Candidate& c) { return c.admitted; });
            if (!touched && reach > 0.0) {
                auto scan = [&](const RestMesh& m, const std::vector<UvTriangle>& uv, bool is_apron) {
                    for (std::size_t t = 0; t < uv.size(); ++t) {
                        if (!(std::abs(uv[t].det) > 0.0)) continue;
                        Candidate c = candidate(m, int(t), uv[t], p, is_apron);
                        const double border = is_apron ? c.tie : c.distance;
                        if (border > reach + kUvRounding) continue;
                        c.admitted = border <= reach;
                        c.borderline = std::abs(border - reach) <= kUvRounding;
                        near.push_back(c);
                    }
                };
                scan(apron, apron_uv, true);
                scan(mesh, mesh_uv, false);
            }
            const std::vector<Candidate>& list = touched ? touching : near;
            const Candidate* best = nullptr;  // the first of equals, as the kernel's scan
            for (const Candidate& c : list)
                if (c.admitted && (!best || better(c, *best))) best = &c;
            auto texelOf = [&](const Candidate& c) {
                const UvTriangle& u = (c.mesh == &mesh ? mesh_uv : apron_uv)[std::size_t(c.triangle)];
                const glm::dvec3 rest = interpolate(c, c.w, &RestVertex::position);
                const glm::dvec3 normal = glm::normalize(interpolate(c, c.w, &RestVertex::normal));
                // the footprint for mip-filtered decals: the rest points one texel right and one down
                const glm::dvec3 rest_dx = interpolate(c, weights(u, p + glm::dvec2(texel, 0.0)), &RestVertex::position);
                const glm::dvec3 rest_dy = interpolate(c, weights(u, p - glm::dvec2(0.0, texel)), &RestVertex::position);
                return evaluate.at(rest, normal, rest_dx, rest_dy);
            };
            BakedTexel value;
            // covered or not within rounding (only borderline touching triangles either way)
            bool ambiguous = !touching.empty() && std::all_of(touching.begin(), touching.end(),
                                                              [](const Candidate& c) { return c.borderline; });
            if (best) {
                value = texelOf(*best);
                out.classes[index] = touched ? BakeTexelClass::Covered : BakeTexelClass::Dilated;
                ambiguous = ambiguous || best->borderline;
                // another candidate that rounding could pick instead: a near tie, or one admitted
                // only within rounding that would win; it matters where its texel differs
                for (const Candidate& c : list) {
                    if (ambiguous) break;
                    if (&c == best || !(nearlyTied(c, *best) || (c.borderline && better(c, *best)))) continue;
                    ambiguous = largestDifference(texelOf(c), value) > kSameValue;
                }
            } else if (!list.empty()) {
                ambiguous = true;  // only candidates within rounding of admission
            }
            out.albedo[index] = value.albedo;
            out.orm[index] = value.orm;
            out.emission[index] = value.emission;
            out.ambiguous[index] = ambiguous || value.ambiguous;
        }
    return out;
}

}  // namespace decalcomp::reference
