// The library's reports as dicts of plain values, for scripts to log or test.
#include <pybind11/stl.h>

#include "bindings.hpp"

namespace decalcomp::python {

py::dict statsDict(const CompositeStats& s) {
    py::dict d;
    d["decals"] = s.decals;
    d["tiles"] = s.tiles;
    d["bin_entries"] = s.bin_entries;
    d["kernels_ms"] = s.totalKernelMs();
    d["tile_bounds_ms"] = s.tile_bounds_ms;
    d["binning_ms"] = s.binning_ms;
    d["bin_coarse_ms"] = s.bin_coarse_ms;  // binning_ms in its steps
    d["bin_count_ms"] = s.bin_count_ms;
    d["bin_scan_ms"] = s.bin_scan_ms;
    d["bin_fill_ms"] = s.bin_fill_ms;
    d["shading_ms"] = s.shading_ms;
    d["occlusion_ms"] = s.occlusion_ms;
    d["rest_ms"] = s.rest_ms;
    return d;
}

py::dict frameReportDict(const FrameReport& r) {
    py::dict d;
    d["outputs"] = r.outputs;
    d["warnings"] = r.warnings;
    d["changed_samples"] = r.changed_samples;
    d["camera_source"] = r.camera_source;
    d["camera_solve"] = r.camera_solve ? py::object(py::str(r.camera_solve->summary())) : py::object(py::none());
    d["profile"] = r.mapping.profile;
    d["depth_check"] = r.depth_check.performed ? py::object(py::str(r.depth_check.summary())) : py::object(py::none());
    d["normal_check"] = r.normal_check.performed ? py::object(py::str(r.normal_check.summary())) : py::object(py::none());
    d["beauty"] = r.beauty.rebuilt ? py::object(py::str(r.beauty.summary)) : py::object(py::none());
    d["pixel_filter"] = r.pixel_filter;
    d["chunks_copied"] = r.chunks_copied;
    d["chunks_reencoded"] = r.chunks_reencoded;
    d["pixels_reencoded"] = r.pixels_reencoded;
    d["stats"] = statsDict(r.stats);
    return d;
}

}  // namespace decalcomp::python
