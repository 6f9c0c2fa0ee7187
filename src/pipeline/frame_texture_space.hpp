#pragma once
// A frame's side of texture-space decals (docs/texture-space.md): the UV pass must be there, its v
// direction is settled against the rest meshes, and a binding no pixel reaches is reported.
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// For frames whose decals include texture-space ones (after the masks are evaluated): throws
// Error(Input) naming `label` when the frame has no UV pass; sets gbuffer.uv_v_down from
// `uv_v_down` (--uv-origin) or, when nullopt, from whichever reading of v puts more of the bound
// objects' pixels on their meshes (a warning says when that is top-down); warns once per binding
// whose object has no pixel on its mesh.
void settleTextureSpace(const DecalScene& scene, const std::vector<Decal>& decals, const ChannelMapping& mapping,
                        std::optional<bool> uv_v_down, const std::string& label, GBuffer& gbuffer,
                        std::vector<std::string>& warnings);

}  // namespace decalcomp
