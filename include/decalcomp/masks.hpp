#pragma once
// Decal masks evaluated per frame (docs/scene-format.md, "Masks"): object-id and Cryptomatte
// selections become one weight plane per DecalScene::masks entry, which the shading multiplies
// into each decal's blend factor.
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/decal.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// Fills frame.mask_weights with one single-component plane per scene.masks entry, over the
// frame's pixels (the mapping's G-buffer window):
//  - ids: 1 where the rounded object-id value is in include_ids (or include_ids is empty) and not
//    in exclude_ids, else 0;
//  - Cryptomatte: the summed coverage of the rank pairs whose id is one of the matched names
//    (clamped to [0,1]), so object silhouettes give antialiased decal edges;
//  - both: the product.
// Throws Error(Input) naming the file and channel or header field: ids without an object-id pass,
// ids the id channel's type cannot represent, an unknown Cryptomatte layer (listing those present),
// a manifest that is not valid JSON, Cryptomatte id channels that are not FLOAT. Appends to
// `warnings` (when not null) a line per name pattern that matches nothing, and per id pass with
// non-integer values.
void evaluateMasks(const std::vector<ExrImage>& files, const ChannelMapping& mapping, const DecalScene& scene,
                   GBuffer& frame, std::vector<std::string>* warnings);
// The same for a single file (copies it; pipelines that hold their files use the form above).
void evaluateMasks(const ExrImage& image, const ChannelMapping& mapping, const DecalScene& scene, GBuffer& frame,
                   std::vector<std::string>* warnings);

// ---- Cryptomatte (Psyop specification 1.2) ----

// MurmurHash3, x86 32-bit variant, of the bytes of `data` (Cryptomatte hashes names with seed 0).
std::uint32_t murmurHash3_32(std::string_view data, std::uint32_t seed = 0);

// The specification's "uint32_to_float32" conversion: the hash's bits as a float with the
// exponent clamped to [1, 254], so no id is zero, denormal, infinite or NaN.
float cryptomatteFloatFromHash(std::uint32_t hash);
std::uint32_t cryptomatteBitsFromHash(std::uint32_t hash);  // the bits of that float

// One Cryptomatte layer as its metadata describes it (cryptomatte/<key>/...).
struct CryptomatteLayer {
    std::string file;        // the EXR whose header holds it
    std::string key;         // metadata key, e.g. "542cafa"
    std::string name;        // e.g. "ViewLayer.CryptoObject" (the channels' prefix)
    std::string hash;        // "MurmurHash3_32" (empty when absent)
    std::string conversion;  // "uint32_to_float32" (empty when absent)
    std::string manifest;    // inline manifest JSON (empty when absent)
    std::string manif_file;  // sidecar manifest path as written (empty when absent)
};

// Every layer described in the files' part headers (one entry per file and key).
std::vector<CryptomatteLayer> cryptomatteLayers(const std::vector<ExrImage>& files);

// The layer's manifest, name -> hash, from the header or the sidecar (relative to the EXR's
// folder). Empty when the layer has none. Throws Error(Input) naming the file and the
// cryptomatte/<key>/manifest (or manif_file) field when it is not valid JSON or not a map of names
// to 8-digit hexadecimal hashes.
std::map<std::string, std::uint32_t> cryptomatteManifest(const CryptomatteLayer& layer);

}  // namespace decalcomp
