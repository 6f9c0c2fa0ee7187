#pragma once
// Provenance: what decalcomp records in the header of every file it composites into, so a
// compositor can tell which tool, scene and decals made a frame, and a second run of the same
// scene over its own output is refused instead of stacking every decal twice (docs/cli.md,
// "Provenance"). Attributes, all strings, on every part:
//   decalcomp/version    the library's version
//   decalcomp/scene      the scene's fingerprint, "fnv1a64:<16 hex digits>" of its canonical JSON
//   decalcomp/sceneFile  the scene file as given ("" for a scene built in code)
//   decalcomp/decals     the decals composited into this frame, a JSON array of names
//   decalcomp/scenes     every scene composited into the file so far, oldest first (JSON array)
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <OpenEXR/ImfHeader.h>

#include "decalcomp/decal.hpp"

namespace decalcomp {

struct ProvenanceRecord {
    std::string version;
    std::string scene;       // fingerprint
    std::string scene_file;
    std::vector<std::string> decals;
    std::vector<std::string> scenes;  // history, this record's scene last
};

// FNV-1a (64 bit) of `canonical_json` (nlohmann's dump(): keys sorted, no whitespace), spelled
// "fnv1a64:%016x". Not a cryptographic hash: it tells scenes apart, it does not authenticate them.
std::string sceneFingerprint(const std::string& canonical_json);

// The record in `header`; nullopt when the file was not written by decalcomp. Throws
// Error(Input) naming `file` and the attribute when one is there but malformed.
std::optional<ProvenanceRecord> readProvenance(const Imf::Header& header, const std::string& file);

// The record of compositing `scene` (its decals alive on this frame: `decals`) into a file whose
// own record is `previous`.
ProvenanceRecord composeProvenance(const DecalScene& scene, const std::vector<Decal>& decals,
                                   const std::optional<ProvenanceRecord>& previous);

// The header attributes (name -> value) that carry `record`.
std::map<std::string, std::string> provenanceAttributes(const ProvenanceRecord& record);

}  // namespace decalcomp
