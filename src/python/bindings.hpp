#pragma once
// The Python module's parts (docs/python.md): each file binds one concept.
#include <pybind11/pybind11.h>

#include <map>
#include <optional>
#include <string>

#include "decalcomp/camera.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/frame.hpp"

namespace decalcomp::python {

namespace py = pybind11;

void bindErrors(py::module_& m);      // decalcomp.Error and its kinds
void bindDevices(py::module_& m);     // devices(), Device
void bindScene(py::module_& m);       // Scene, Camera
void bindCompositor(py::module_& m);  // Compositor: arrays and files
void bindBatch(py::module_& m);       // batch()
void bindBake(py::module_& m);        // bake()

// A Camera, a (world_to_camera, projection) pair of 4x4 arrays, or a camera JSON path.
Camera cameraFrom(const py::object& value);

// "decalcomp: note: MESSAGE" on sys.stderr, from any thread (it takes the GIL): a device's notice
// of a long kernel build (ComputeDevice::setSlowBuildNotice), as the CLI prints it (devices.cpp).
void writeNote(const std::string& message);

// Reports as dicts of plain Python values (report.cpp).
py::dict statsDict(const CompositeStats& stats);
py::dict frameReportDict(const FrameReport& report);

// kwargs[key], or an empty object when it is absent or None (None means "the default").
py::object argument(const py::kwargs& kwargs, const char* key);

// The CLI's spellings of single options, each a Error(Usage) naming `key=value` when wrong:
// depth planar|radial|ndc|position; normals world|camera[,signed|packed|unsigned] (packed is
// nullopt when the encoding is not given); uv_origin bottom|top (true: top, V runs down).
DepthConvention depthArgument(const std::string& value);
struct NormalsArgument {
    NormalSpace space = NormalSpace::World;
    std::optional<bool> packed;
};
NormalsArgument normalsArgument(const std::string& value);
bool uvOriginTopArgument(const std::string& value);

// Keyword arguments shared by files and batches, as the CLI's mapping flags: profile,
// profile_files, layer, channels {attr: [channel...] or "a,b,c"}, depth, reversed_z,
// normals "world|camera[,signed|packed]", add_channels {attr: value}. Throws Error(Usage).
MappingOptions mappingOptions(const py::kwargs& kwargs);
// {attr: path} -> Attribute-keyed paths (--pass). Throws Error(Usage) for unknown attributes.
std::map<Attribute, std::string> passFiles(const py::object& passes);
// Keyword arguments no binding consumed: a TypeError naming them, as Python does.
void rejectUnknown(const py::kwargs& kwargs, std::initializer_list<const char*> known, const char* function);

}  // namespace decalcomp::python
