// decalcomp.Scene (a decal scene loaded once, composited into many frames) and decalcomp.Camera.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

#include "bindings.hpp"
#include "decalcomp/camera.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp::python {

namespace {

// A 4x4 array in row-major mathematical order (m[row][col]) -> GLM's column-major matrix.
glm::dmat4 matrixFromArray(const py::handle& value, const char* what) {
    py::array_t<double, py::array::c_style | py::array::forcecast> a;
    try {
        a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    } catch (const py::error_already_set&) {
    }
    if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
        throw Error(ErrorKind::Usage, fmt::format("camera: {}: expected a 4x4 array", what));
    double rows[4][4];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            rows[r][c] = a.at(r, c);
            if (!std::isfinite(rows[r][c]))
                throw inputError(fmt::format("camera: {}[{}][{}] is not finite", what, r, c));
        }
    const glm::dmat4 m = matrixFromRows(rows);
    if (!(std::abs(glm::determinant(m)) > 1e-300))
        throw inputError(fmt::format("camera: {} is not invertible", what));
    return m;
}

py::array_t<double> arrayFromMatrix(const glm::dmat4& m) {
    py::array_t<double> a({4, 4});
    auto view = a.mutable_unchecked<2>();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) view(r, c) = m[c][r];
    return a;
}

}  // namespace

Camera cameraFrom(const py::object& value) {
    if (py::isinstance<Camera>(value)) return value.cast<Camera>();
    if (py::isinstance<py::str>(value)) return loadCameraJson(value.cast<std::string>());
    if (py::isinstance<py::sequence>(value) && py::len(value) == 2) {
        const py::sequence pair = value.cast<py::sequence>();
        Camera camera;
        camera.world_to_camera = matrixFromArray(pair[0], "world_to_camera");
        camera.projection = matrixFromArray(pair[1], "projection");
        camera.source = "Python arrays";
        return camera;
    }
    throw Error(ErrorKind::Usage, "camera: expected a decalcomp.Camera, (world_to_camera, projection) 4x4 arrays "
                                  "or a camera JSON path");
}

void bindScene(py::module_& m) {
    py::class_<DecalScene, std::shared_ptr<DecalScene>>(
        m, "Scene", "A decal scene (docs/scene-format.md): load it once, composite it into many frames.")
        .def_static(
            "load", [](const std::string& path, const std::string& ocio) { return loadScene(path, {ocio}); },
            py::arg("path"), py::arg("ocio") = "", py::call_guard<py::gil_scoped_release>(),
            "Loads a scene JSON file; texture paths are relative to it. `ocio`: the OpenColorIO config of its "
            "colour spaces (default: $OCIO).")
        .def_static(
            "from_json",
            [](const std::string& text, const std::string& label, const std::string& base_dir, const std::string& ocio) {
                return parseScene(text, label, base_dir, {ocio});
            },
            py::arg("text"), py::arg("label") = "<json>", py::arg("base_dir") = ".", py::arg("ocio") = "",
            py::call_guard<py::gil_scoped_release>(),
            "Parses scene JSON text; `label` names it in errors, relative paths resolve against `base_dir`.")
        .def_static(
            "from_dict",
            [](const py::dict& scene, const std::string& label, const std::string& base_dir, const std::string& ocio) {
                const std::string text = py::module_::import("json").attr("dumps")(scene).cast<std::string>();
                py::gil_scoped_release release;
                return parseScene(text, label, base_dir, {ocio});
            },
            py::arg("scene"), py::arg("label") = "<dict>", py::arg("base_dir") = ".", py::arg("ocio") = "",
            "The same from a dict of the scene format.")
        .def_readonly("source", &DecalScene::source)
        .def_readonly("warnings", &DecalScene::warnings, "Found while loading (duplicate decal names...)")
        .def_readonly("working_space", &DecalScene::working_space,
                      "The OpenColorIO space colour textures were converted to (\"\": built-in decode)")
        .def_readonly("colour_config", &DecalScene::colour_config, "The OpenColorIO config read (\"\": none)")
        .def_property_readonly(
            "decal_names",
            [](const DecalScene& s) {
                std::vector<std::string> names;
                for (const Decal& d : s.decals) names.push_back(d.name);
                return names;
            },
            "The decals' names in blend order.")
        .def_property_readonly("animated", &isAnimated)
        .def("__len__", [](const DecalScene& s) { return s.decals.size(); })
        .def("__repr__", [](const DecalScene& s) {
            return fmt::format("<decalcomp.Scene '{}': {} decals, {} textures>", s.source, s.decals.size(),
                               s.textures.size());
        });

    py::class_<Camera>(m, "Camera",
                       "A pinhole or orthographic camera: world -> camera (right-handed, looking down -Z) and an "
                       "OpenGL projection to NDC, both 4x4 in row-major mathematical order (m[row][col]).")
        .def(py::init([](const py::object& world_to_camera, const py::object& projection) {
                 Camera camera;
                 camera.world_to_camera = matrixFromArray(world_to_camera, "world_to_camera");
                 camera.projection = matrixFromArray(projection, "projection");
                 camera.source = "Python arrays";
                 return camera;
             }),
             py::arg("world_to_camera"), py::arg("projection"))
        .def_static("load", &loadCameraJson, py::arg("path"), "Reads a camera JSON sidecar (docs/cli.md).")
        .def_property_readonly("world_to_camera", [](const Camera& c) { return arrayFromMatrix(c.world_to_camera); })
        .def_property_readonly("projection", [](const Camera& c) { return arrayFromMatrix(c.projection); })
        .def_readonly("source", &Camera::source)
        .def("__repr__", [](const Camera& c) {
            return fmt::format("<decalcomp.Camera {} from {}>", c.isOrthographic() ? "orthographic" : "perspective",
                               c.source);
        });
}

}  // namespace decalcomp::python
