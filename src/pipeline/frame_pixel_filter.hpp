#pragma once
// Which pixel filter a frame's passes were rendered with (docs/pixel-filter.md "Choosing").
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer.hpp"
#include "decalcomp/pixel_filter.hpp"

namespace decalcomp {

// --pixel-filter when given; else a `pixelFilter` string attribute in an input's header; else
// none when the frame's normal pass has hard edges (unit normals only, and neighbours that turn
// sharply: its passes were not filtered, as in 1-spp renders, tiny filters, game-engine dumps);
// else the profile's default (inconclusive where the normal pass has no sharp turn to judge by).
PixelFilterChoice choosePixelFilter(const std::vector<ExrImage>& files, const std::string& profile,
                                    const std::vector<std::string>& profile_files, const GBuffer& gbuffer,
                                    const std::optional<PixelFilter>& requested);

}  // namespace decalcomp
