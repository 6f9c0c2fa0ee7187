// decalcomp.devices() and decalcomp.Device: the OpenCL devices, as `decalcomp devices` lists them.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "decalcomp/device.hpp"

namespace decalcomp::python {

void writeNote(const std::string& message) {
    py::gil_scoped_acquire acquire;
    try {
        const py::object err = py::module_::import("sys").attr("stderr");
        if (!err.is_none()) err.attr("write")("decalcomp: note: " + message + "\n");  // None under pythonw
    } catch (const py::error_already_set&) {  // a stream that cannot take it: the note is dropped
    }
}

void bindDevices(py::module_& m) {
    py::class_<DeviceInfo>(m, "Device", "An OpenCL device (pass its index or part of its name as `device=`).")
        .def_readonly("index", &DeviceInfo::index)
        .def_readonly("name", &DeviceInfo::name)
        .def_readonly("vendor", &DeviceInfo::vendor)
        .def_readonly("platform", &DeviceInfo::platform)
        .def_readonly("version", &DeviceInfo::version)
        .def_readonly("type", &DeviceInfo::type, "'gpu', 'cpu', 'accelerator' or 'other'")
        .def("__repr__", [](const DeviceInfo& d) {
            return fmt::format("<decalcomp.Device {} '{}' ({}, {})>", d.index, d.name, d.type, d.platform);
        });
    m.def("devices", &listDevices, py::call_guard<py::gil_scoped_release>(),
          "Every OpenCL device of every platform, in the order `device=INDEX` counts them.");
}

}  // namespace decalcomp::python
