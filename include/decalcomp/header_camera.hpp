#pragma once
// Cameras in EXR headers: the standard worldToCamera / worldToNDC attributes <-> Camera.
#include <OpenEXR/ImfHeader.h>

#include <optional>
#include <string>

#include "decalcomp/camera.hpp"

namespace decalcomp {

// Reads the standard worldToCamera / worldToNDC attributes (RenderMan conventions: left-handed
// camera looking down +Z, row-vector Imath storage, NDC x right and y down in [0,1] over the
// display window) and converts them to decalcomp's conventions. Returns nullopt when absent;
// throws Error(Input) when present but singular or inconsistent.
std::optional<Camera> cameraFromExrHeader(const Imf::Header& header, const std::string& file);
// The inverse, for the generator and round-trip tests.
void writeCameraToExrHeader(const Camera& camera, Imf::Header& header);

}  // namespace decalcomp
