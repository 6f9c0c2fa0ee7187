#pragma once
// Decal masks evaluated per frame (docs/scene-format.md, "Masks"): object-id and Cryptomatte
// selections become one weight plane per DecalScene::masks entry, which the shading multiplies
// into each decal's blend factor.
#include <string>
#include <vector>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/cryptomatte.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// Fills frame.mask_weights with one single-component plane per scene.masks entry, over the
// frame's pixels (the mapping's G-buffer window):
//  - ids: 1 where the rounded object-id value is in include_ids (or include_ids is empty) and not
//    in exclude_ids, else 0;
//  - Cryptomatte: the summed coverage of the rank pairs whose id is one of the selected names
//    (clamped to [0,1]), so object silhouettes give antialiased decal edges;
//  - both: the product.
// Throws Error(Input) naming the file and channel or header field: ids without an object-id pass,
// ids the id channel's type cannot represent, an unknown Cryptomatte layer (listing those present),
// Cryptomatte id channels that are not FLOAT, an unsupported hash or conversion.
// Appends to `warnings` (when not null), each "FILE: FIELD: what, and what to check": a name
// pattern that selects nothing, a manifest that is missing, broken or partly unreadable (the
// layer is then keyed by hash, as the specification asks of decoders), an id pass with
// non-integer values. Warnings name file i as file_labels[i] when that is given and not empty (a
// batch gives its patterns, so every frame words a warning the same), else by its path.
void evaluateMasks(const std::vector<ExrImage>& files, const ChannelMapping& mapping, const DecalScene& scene,
                   GBuffer& frame, std::vector<std::string>* warnings,
                   const std::vector<std::string>& file_labels = {});
// The same for a single file (copies it; pipelines that hold their files use the form above).
void evaluateMasks(const ExrImage& image, const ChannelMapping& mapping, const DecalScene& scene, GBuffer& frame,
                   std::vector<std::string>* warnings);

// Planes without files (the Python module's arrays): object-id masks from the frame's ObjectId
// plane. Throws Error(Input) naming `label` when a mask needs Cryptomatte (only files carry its
// manifest and ranks) or ids without an ObjectId plane.
void evaluateIdMasks(const DecalScene& scene, GBuffer& frame, const std::string& label);

}  // namespace decalcomp
