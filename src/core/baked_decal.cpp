// The decal that reads a UV-space bake in place of a bake-mode texture-space decal (bake.hpp).
#include "decalcomp/bake.hpp"

namespace decalcomp {

namespace {

bool isOrmTarget(DecalTarget t) {
    return t == DecalTarget::AmbientOcclusion || t == DecalTarget::Roughness || t == DecalTarget::Metallic;
}

}  // namespace

Decal bakedDecal(const Decal& decal, int albedo, int orm, int emission) {
    Decal out = decal;
    out.baked = true;
    // A flat texture looked up at (u, 1 - v): the kind's projection, fades and constants are baked.
    out.kind = DecalKind::Box;
    out.albedo_texture = albedo;
    out.normal_texture = -1;
    out.orm_texture = orm;
    out.emission_texture = emission;
    out.angle_fade_deg = {0.0, 0.0};
    out.axis_fade = 0.0;
    out.distance_fade = {0.0, 0.0};
    out.occlusion = {};
    // Bilinear in the layer; a mip-filtered decal reads the layer's mip chain.
    out.filter = decal.filter == TextureFilter::Mip ? TextureFilter::Mip : TextureFilter::Linear;
    for (int t = 0; t < kDecalTargets; ++t) {
        TargetEffect& e = out.effects[std::size_t(t)];
        if (!decalAffects(decal, DecalTarget(t))) e.factor = 0.0f;  // the coverage layer is no value
        // ORM constants stay: the ORM layer is empty where the decal's ORM map is transparent (exact
        // mode skips the map's channels there, not the constants'), so the layer cannot carry them.
        if (!isOrmTarget(DecalTarget(t))) e.value.reset();
    }
    return out;
}

}  // namespace decalcomp
