#pragma once
// Which space and encoding a normal pass uses, checked against the geometry: the normals must
// agree with the surfaces the depth (or position) pass describes.
#include <optional>
#include <string>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

struct NormalCheck {
    bool performed = false;
    std::string reason;       // why not, or the verdict in words
    std::size_t pixels = 0;   // geometry pixels compared
    // Mean cosine between the stored normals, read each way, and the normals of the surfaces
    // rebuilt from depth: world/camera space x signed/packed.
    double agreement[2][2] = {{0, 0}, {0, 0}};
    std::optional<NormalEncoding> verdict;  // when one reading fits clearly better than the others
    std::string summary() const;
};

// What the user fixed with --normals: the readings that disagree do not compete.
struct NormalConstraints {
    std::optional<NormalSpace> space;
    std::optional<bool> packed;
};

// Compares up to ~4000 pixels on smooth surfaces (both neighbours along each axis close in depth).
NormalCheck checkNormalEncoding(const GBuffer& gbuffer, const Camera& camera, const NormalConstraints& fixed = {});

const char* normalSpaceName(NormalSpace space);  // "world", "camera"

}  // namespace decalcomp
