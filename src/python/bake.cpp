// decalcomp.bake(): `decalcomp bake` through the library's bakeFiles (decalcomp/bake.hpp), the
// same files byte for byte, the GIL released while it loads, bakes and writes.
#include <pybind11/stl.h>

#include <memory>

#include "bindings.hpp"
#include "decalcomp/bake.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp::python {

namespace {

// A str or os.PathLike as a path.
std::string pathOf(const py::object& value) { return py::module_::import("os").attr("fspath")(value).cast<std::string>(); }
bool isPath(const py::object& value) { return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__"); }

py::dict bake(const py::object& scene, const py::object& output_dir, const py::object& decal, bool png,
              const py::object& device, const py::object& ocio) {
    if (!isPath(output_dir)) throw Error(ErrorKind::Usage, "bake: output_dir: expected a folder path");
    BakeFilesRequest request;
    request.output = pathOf(output_dir);
    request.png = png;
    if (!decal.is_none()) request.decal = decal.cast<std::string>();
    if (!device.is_none()) request.device = device.cast<std::string>();
    std::shared_ptr<DecalScene> loaded;
    std::string path;
    if (isPath(scene)) {
        path = pathOf(scene);
    } else if (py::isinstance<DecalScene>(scene)) {
        loaded = scene.cast<std::shared_ptr<DecalScene>>();
    } else {
        throw Error(ErrorKind::Usage, "bake: scene: expected a scene JSON path or a decalcomp.Scene");
    }
    const std::string ocio_config = ocio.is_none() ? "" : ocio.cast<std::string>();
    BakeFilesResult result;
    {
        py::gil_scoped_release release;
        if (!loaded) {
            loaded = std::make_shared<DecalScene>(loadScene(path, {ocio_config}));
            request.scene_file = path;
        }
        result = bakeFiles(*loaded, request);
    }
    py::list files;
    for (const BakedFile& f : result.files) {
        py::dict d;
        d["decal"] = f.decal;
        d["exr"] = f.exr;
        d["png"] = f.png.empty() ? py::object(py::none()) : py::object(py::str(f.png));
        d["width"] = f.width;
        d["height"] = f.height;
        d["dilation"] = f.dilation;
        d["device"] = f.device;
        files.append(d);
    }
    py::dict out;
    out["files"] = files;
    out["warnings"] = result.warnings;
    return out;
}

}  // namespace

void bindBake(py::module_& m) {
    m.def("bake", &bake, py::arg("scene"), py::arg("output_dir"), py::kw_only(), py::arg("decal") = py::none(),
          py::arg("png") = true, py::arg("device") = py::none(), py::arg("ocio") = py::none(),
          "Bakes the scene's bake-mode texture-space decals (a scene JSON path or a decalcomp.Scene) into "
          "output_dir/DECAL.exr and, with png, DECAL.png, as `decalcomp bake` does (docs/texture-space.md "
          "\"Bake mode\"). `decal`: only the decal of that name. Returns {'files': [{'decal', 'exr', 'png', "
          "'width', 'height', 'dilation', 'device'}...], 'warnings': [...]}.");
}

}  // namespace decalcomp::python
