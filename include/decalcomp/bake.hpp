#pragma once
// Bake mode of texture-space decals (seed 003; docs/texture-space.md "Bake mode"): the decal
// evaluated once per texel of a UV-space layer of its rest mesh, on the device, then read at each
// pixel's UV. Built once per scene (Compositor::setScene), exported by `decalcomp bake`, and
// reusable across runs through the scene's "baked" file.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/decal.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/rest_mesh.hpp"

namespace decalcomp {

// One decal's bake: linear, premultiplied RGBA layers, row 0 at v = 1 (the top of the UV square,
// as DCCs show it). The albedo layer's alpha is the decal's coverage times its fades (also when
// the decal leaves the albedo alone); ORM (ao, roughness, metallic) and emission share it and are
// there when the decal writes them.
struct BakedLayers {
    int width = 0, height = 0;
    Texture2D albedo;
    std::optional<Texture2D> orm, emission;
    double bake_kernel_ms = 0;  // the bake kernel's device time where the device profiles (else 0)
};

// The apron of a mesh's UV islands: one triangle outside each island border edge, its edge 0-1
// that border. Across a UV seam it is the face on the other side (the same 3D edge, another UV
// edge) unfolded into this island's chart with its real rest positions; where the mesh ends it is
// the border face mirrored across the edge in UV, its rest positions extended on the face's plane.
RestMesh uvApron(const RestMesh& mesh);

// Bakes one texture-space decal of `scene` (decal.rest_mode == Bake) at its bake_resolution with
// its bake_dilation. Throws Error(Input) for decals bake mode does not carry (normal maps).
BakedLayers bakeDecal(ComputeDevice& device, const DecalScene& scene, const Decal& decal);

// The decal that reads `layers`' textures (scene texture indices; -1 = none) at the pixel's UV in
// place of `decal`: fades and constants are in the bake (ORM constants are also kept on the decal:
// the ORM layer is empty where the ORM map is transparent); targets the decal leaves alone stay so.
Decal bakedDecal(const Decal& decal, int albedo, int orm, int emission);

// Identifies a mesh's UVs and rest positions (FNV-1a 64), so a baked file names the mesh it fits.
std::uint64_t restMeshFingerprint(const RestMesh& mesh);

// The baked file (docs/texture-space.md "Bake mode"): an EXR with RGBA (albedo), orm.RGBA and
// emission.RGBA as they are baked, and the mesh fingerprint in its header. Throws Error(Input).
BakedLayers readBakedLayers(const std::string& path, const RestMesh& mesh);
// Writes the EXR (float) and, when `png` is not empty, the albedo as an 8-bit sRGB PNG with straight
// alpha, each through a temporary file renamed into place. Throws Error(Output).
void writeBakedLayers(const BakedLayers& layers, const RestMesh& mesh, const std::string& decal_name,
                      const std::string& exr, const std::string& png);

// `decalcomp bake` as a library call (docs/cli.md "bake"; the CLI and the Python module run it):
// OUTPUT/DECAL.exr and, with `png`, OUTPUT/DECAL.png for each bake-mode decal of the scene (or the
// one named `decal`), DECAL being its name with anything but letters, digits, '.', '-' and '_'
// replaced by '_'. Every output is checked before the device is opened: two decals may not write
// the same file, and no output may be a file the scene reads.
struct BakeFilesRequest {
    std::string output;      // the folder (created when missing)
    std::string decal;       // only this decal (empty: every bake-mode decal)
    bool png = true;         // also the 8-bit albedo PNG
    std::string device;      // ComputeDevice selector ("": GPU, else CPU)
    std::string scene_file;  // the scene's file, for messages and the overwrite check ("": scene.source)
};
struct BakedFile {
    std::string decal, exr, png;  // png empty without one
    int width = 0, height = 0, dilation = 0;
    std::string device;           // the OpenCL device's name
};
struct BakeFilesResult {
    std::vector<BakedFile> files;
    std::vector<std::string> warnings;  // decals that read a "baked" file and were not baked again
};
// Throws Error(Usage) for a bad output or name clash, Error(Input) when nothing is to be baked,
// and what bakeDecal and writeBakedLayers throw.
BakeFilesResult bakeFiles(const DecalScene& scene, const BakeFilesRequest& request);

}  // namespace decalcomp
