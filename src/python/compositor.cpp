// decalcomp.Compositor: one OpenCL device and one loaded scene, composited into numpy planes in
// process or into EXR files through the frame pipeline (decalcomp/frame.hpp), the CLI's path.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>

#include "bindings.hpp"
#include "decalcomp/compositor.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/frame.hpp"
#include "decalcomp/masks.hpp"
#include "decalcomp/pixel_filter.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp::python {

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// A plane the caller handed in: float32 C-contiguous (converted once when it is not), H x W or
// H x W x C with C the attribute's components.
struct InputPlane {
    Attribute attribute;
    FloatArray array;
};

std::string knownAttributes() {
    std::vector<std::string> names;
    for (Attribute a : kAllAttributes) names.push_back(attributeName(a));
    return fmt::format("{}", fmt::join(names, ", "));
}

std::vector<InputPlane> inputPlanes(const py::dict& planes, int& width, int& height) {
    std::vector<InputPlane> result;
    width = height = -1;
    for (const auto& [key, value] : planes) {
        const std::string name = key.cast<std::string>();
        const auto attribute = attributeFromName(name);
        if (!attribute) throw inputError(fmt::format("planes['{}']: unknown attribute (known: {})", name, knownAttributes()));
        FloatArray array = FloatArray::ensure(value);
        if (!array) throw inputError(fmt::format("planes['{}']: not an array of numbers", name));
        const int components = attributeComponents(*attribute);
        const bool shape_ok = (array.ndim() == 3 && array.shape(2) == components) || (array.ndim() == 2 && components == 1);
        if (!shape_ok)
            throw inputError(fmt::format("planes['{}']: shape {}: expected (height, width{})", name,
                                         fmt::join(std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim()), "x"),
                                         components == 1 ? "" : fmt::format(", {}", components)));
        const int h = int(array.shape(0)), w = int(array.shape(1));
        if (width < 0) width = w, height = h;
        if (w != width || h != height)
            throw inputError(fmt::format("planes['{}']: {}x{} pixels, the other planes {}x{}", name, w, h, width, height));
        result.push_back({*attribute, std::move(array)});
    }
    if (result.empty() || width <= 0 || height <= 0) throw inputError("planes: no pixels (give at least depth and albedo)");
    return result;
}

// A result plane handed to numpy without a copy: the array owns the samples' vector.
py::array ownedArray(Plane&& plane, int width, int height) {
    auto* samples = new std::vector<float>(std::move(plane.samples));
    py::capsule owner(samples, [](void* p) { delete static_cast<std::vector<float>*>(p); });
    std::vector<py::ssize_t> shape = {height, width};
    if (plane.components > 1) shape.push_back(plane.components);
    return py::array_t<float>(shape, samples->data(), owner);
}

class PyCompositor {
public:
    PyCompositor(const std::string& device, std::shared_ptr<const DecalScene> scene)
        : device_(std::make_unique<ComputeDevice>(device)), compositor_(std::make_unique<Compositor>(*device_)) {
        device_->setSlowBuildNotice(slowBuildNoticeAfter(), writeNote);  // every call releases the GIL
        if (scene) setScene(std::move(scene));
    }

    void setScene(std::shared_ptr<const DecalScene> scene) {
        compositor_->setScene(*scene);
        scene_ = std::move(scene);
        animated_decals_ = false;
    }

    const DecalScene& scene() const {
        if (!scene_) throw Error(ErrorKind::Usage, "Compositor: no scene (give one to Compositor() or set_scene())");
        return *scene_;
    }

    // The decals at `frame` (animated scenes), or the scene's own.
    void selectDecals(const std::optional<double>& frame) {
        if (frame) {
            compositor_->setDecals(decalsAtFrame(scene().decals, *frame));
            animated_decals_ = true;
        } else if (animated_decals_) {
            compositor_->setDecals(scene().decals);
            animated_decals_ = false;
        }
    }

    py::dict composite(const py::dict& planes, const py::object& camera_arg, const std::string& depth,
                       bool reversed_z, const std::string& normals, const std::string& pixel_filter,
                       const std::string& uv_origin, std::optional<double> frame, bool binned) {
        const DecalScene& decals = scene();
        const Camera camera = cameraFrom(camera_arg);
        GBuffer gbuffer;
        gbuffer.depth_convention = depthArgument(depth);
        gbuffer.reversed_z = reversed_z;
        const NormalsArgument normal_encoding = normalsArgument(normals);
        gbuffer.normal_encoding.space = normal_encoding.space;
        gbuffer.normal_encoding.packed = normal_encoding.packed.value_or(false);  // signed unless told
        gbuffer.pixel_filter = parsePixelFilter(pixel_filter, "pixel_filter");
        gbuffer.uv_v_down = uvOriginTopArgument(uv_origin);

        std::vector<InputPlane> inputs = inputPlanes(planes, gbuffer.width, gbuffer.height);
        gbuffer.display_width = gbuffer.width;
        gbuffer.display_height = gbuffer.height;
        std::vector<Attribute> changed;
        {
            py::gil_scoped_release release;  // the arrays stay referenced by `inputs`
            for (const InputPlane& in : inputs) {
                Plane& plane = gbuffer.planes[in.attribute];
                plane.components = attributeComponents(in.attribute);
                plane.samples.assign(in.array.data(), in.array.data() + in.array.size());
            }
            evaluateIdMasks(decals, gbuffer, "planes");
            selectDecals(frame);
            CompositeOptions options;
            options.binned = binned;
            last_stats_ = compositor_->composite(gbuffer, camera, options);
            for (Attribute a : compositedAttributes(decals))
                if (gbuffer.has(a)) changed.push_back(a);
        }
        py::dict result;
        for (Attribute a : changed)
            result[attributeName(a)] = ownedArray(std::move(gbuffer.planes.at(a)), gbuffer.width, gbuffer.height);
        return result;
    }

    py::dict compositeFiles(const py::object& inputs, const std::string& output, const py::kwargs& kwargs) {
        rejectUnknown(kwargs,
                      {"camera", "passes", "preview", "overwrite_input", "force", "profile", "profile_files", "layer", "channels",
                       "depth", "reversed_z", "normals", "add_channels", "pixel_filter", "uv_origin", "frame", "binned"},
                      "composite_files");
        FrameSources sources;
        sources.inputs = py::isinstance<py::str>(inputs) ? std::vector<std::string>{inputs.cast<std::string>()}
                                                         : inputs.cast<std::vector<std::string>>();
        if (sources.inputs.empty()) throw Error(ErrorKind::Usage, "composite_files: no input files");
        if (auto camera = argument(kwargs, "camera")) {
            if (py::isinstance<py::str>(camera)) sources.camera_json = camera.cast<std::string>();
            else sources.camera = cameraFrom(camera);
        }
        auto passes = argument(kwargs, "passes");
        sources.pass_files = passFiles(passes ? passes : py::none());
        FrameTargets targets;
        targets.output = output;
        if (auto v = argument(kwargs, "preview")) targets.preview = v.cast<std::string>();
        if (auto v = argument(kwargs, "overwrite_input")) targets.overwrite_input = v.cast<bool>();
        if (auto v = argument(kwargs, "force")) targets.force = v.cast<bool>();
        FrameOptions options;
        options.mapping = mappingOptions(kwargs);
        if (auto v = argument(kwargs, "pixel_filter")) {  // "auto" (the default) and "auto:fast" choose per frame
            const std::string text = v.cast<std::string>();
            options.pixel_filter_fast = text == "auto:fast";
            if (text != "auto" && !options.pixel_filter_fast) options.pixel_filter = parsePixelFilter(text, "pixel_filter");
        }
        if (auto v = argument(kwargs, "uv_origin")) options.uv_v_down = uvOriginTopArgument(v.cast<std::string>());
        if (auto v = argument(kwargs, "frame")) options.frame_number = v.cast<double>();
        if (auto v = argument(kwargs, "binned")) options.compositing.binned = v.cast<bool>();

        const DecalScene& decals = scene();
        FrameReport report;
        {
            py::gil_scoped_release release;
            Frame frame(std::move(sources), std::move(targets), std::move(options));
            frame.prepare(decals);
            frame.composite(*compositor_);
            frame.writeBack();
            report = frame.report();
            animated_decals_ = true;  // Frame::composite may have replaced the decals
        }
        return frameReportDict(report);
    }

    const DeviceInfo& device() const { return device_->info(); }
    const CompositeStats& lastStats() const { return last_stats_; }

private:
    std::unique_ptr<ComputeDevice> device_;
    std::unique_ptr<Compositor> compositor_;
    std::shared_ptr<const DecalScene> scene_;
    bool animated_decals_ = false;
    CompositeStats last_stats_;
};

}  // namespace

void bindCompositor(py::module_& m) {
    py::class_<PyCompositor>(m, "Compositor",
                             "One OpenCL device and one scene: build it once, composite many frames. Every call "
                             "releases the GIL while it works.")
        .def(py::init<const std::string&, std::shared_ptr<const DecalScene>>(), py::arg("device") = "",
             py::arg("scene") = nullptr, py::call_guard<py::gil_scoped_release>(),
             "device: '' (first GPU, else CPU), an index, 'gpu', 'cpu' or part of a name")
        .def("set_scene", &PyCompositor::setScene, py::arg("scene"), py::call_guard<py::gil_scoped_release>(),
             "Uploads the scene's textures; later composites use it.")
        .def("composite", &PyCompositor::composite, py::arg("planes"), py::arg("camera"), py::kw_only(),
             py::arg("depth") = "planar", py::arg("reversed_z") = false, py::arg("normals") = "world",
             py::arg("pixel_filter") = "none", py::arg("uv_origin") = "bottom", py::arg("frame") = py::none(),
             py::arg("binned") = true,
             "Composites into numpy planes {attribute: (H, W[, C]) float32}; returns the planes the decals "
             "change, as new arrays. The inputs are not modified.")
        .def("composite_files", &PyCompositor::compositeFiles, py::arg("inputs"), py::arg("output"),
             "Composites EXR files as `decalcomp composite` does; returns the frame's report as a dict.")
        .def_property_readonly("device", &PyCompositor::device, py::return_value_policy::copy)
        .def_property_readonly(
            "last_stats",
            [](const PyCompositor& c) { return statsDict(c.lastStats()); },
            "Device figures of the last array composite: decals, tiles, kernel milliseconds.");
}

}  // namespace decalcomp::python
