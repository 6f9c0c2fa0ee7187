// decalcomp's Python module (docs/python.md). The Python package (python/decalcomp) re-exports it.
#include "bindings.hpp"
#include "decalcomp/version.hpp"

PYBIND11_MODULE(_decalcomp, m) {
    m.doc() = "Decal compositing into rendered G-buffers on OpenCL devices";
    m.attr("__version__") = decalcomp::kVersion;
    decalcomp::python::bindErrors(m);
    decalcomp::python::bindDevices(m);
    decalcomp::python::bindScene(m);
    decalcomp::python::bindCompositor(m);
    decalcomp::python::bindBatch(m);
    decalcomp::python::bindBake(m);
}
