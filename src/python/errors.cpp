// decalcomp.Error (a RuntimeError) and one subclass per ErrorKind, carrying the library's message
// unchanged: the same file and field wording as the CLI's.
#include <CL/opencl.hpp>

#include "bindings.hpp"
#include "decalcomp/device.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp::python {

namespace {

// Owned by the module for the interpreter's life (released: never destroyed after Py_Finalize).
PyObject* g_base = nullptr;
PyObject* g_kinds[4] = {};

PyObject* typeFor(ErrorKind kind) {
    switch (kind) {
        case ErrorKind::Usage: return g_kinds[0];
        case ErrorKind::Input: return g_kinds[1];
        case ErrorKind::Device: return g_kinds[2];
        case ErrorKind::Output: return g_kinds[3];
    }
    return g_base;
}

PyObject* newType(py::module_& m, const char* name, PyObject* base, const char* doc) {
    const std::string qualified = std::string("decalcomp.") + name;
    PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
    if (!type) throw py::error_already_set();
    m.attr(name) = py::handle(type);
    return type;
}

}  // namespace

void bindErrors(py::module_& m) {
    g_base = newType(m, "Error", PyExc_RuntimeError, "A decalcomp failure; str() is the CLI's message.");
    g_kinds[0] = newType(m, "UsageError", g_base, "Bad arguments (the CLI's exit code 2).");
    g_kinds[1] = newType(m, "InputError", g_base, "An unreadable or invalid input file, field, channel or texture (3).");
    g_kinds[2] = newType(m, "DeviceError", g_base, "An OpenCL platform, device, build or runtime failure (4).");
    g_kinds[3] = newType(m, "OutputError", g_base, "An output that cannot be written (5).");
    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const Error& e) {
            PyErr_SetString(typeFor(e.kind()), e.what());
        } catch (const cl::Error& e) {
            PyErr_SetString(g_kinds[2], (std::string(e.what()) + ": " + clErrorName(e.err())).c_str());
        }
    });
}

}  // namespace decalcomp::python
