// decalcomp.batch(): a sequence through the library's batch (decalcomp/batch.hpp), the loop
// `decalcomp batch` runs, with an optional per-frame progress callback.
#include <fmt/format.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <type_traits>

#include "bindings.hpp"
#include "decalcomp/batch.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp::python {

namespace {

const char* statusName(FrameStatus status) {
    switch (status) {
        case FrameStatus::Written: return "written";
        case FrameStatus::Skipped: return "skipped";
        case FrameStatus::Failed: return "failed";
    }
    return "failed";
}

py::dict frameResultDict(const FrameResult& r) {
    py::dict d;
    d["frame"] = r.frame;
    d["status"] = statusName(r.status);
    d["output"] = r.output;
    d["message"] = r.message;
    return d;
}

// Calls progress(frame_result_dict), when given, on runBatch's thread, holding the GIL only for the
// call; a long kernel build's note goes to sys.stderr.
class ProgressCallback : public BatchObserver {
public:
    explicit ProgressCallback(py::object callback) : callback_(std::move(callback)) {}
    ~ProgressCallback() override {
        py::gil_scoped_acquire acquire;
        callback_ = py::object();
    }
    void frameFinished(const FrameResult& result, const BatchProgress&) override {
        if (!callback_) return;
        py::gil_scoped_acquire acquire;
        callback_(frameResultDict(result));  // an exception raised here stops the batch
    }
    void slowBuild(const std::string& message) override { writeNote(message); }

private:
    py::object callback_;
};

py::dict batch(const std::string& input, const std::string& output, const std::string& scene, const py::kwargs& kwargs) {
    rejectUnknown(kwargs,
                  {"extra_inputs", "passes", "preview", "contact_sheet", "frames", "camera", "cameras", "device", "overwrite_input", "force",
                   "resume", "keep_going", "shard", "threads", "queue", "workers", "progress", "profile",
                   "profile_files", "layer", "channels", "depth", "reversed_z", "normals", "add_channels",
                   "pixel_filter", "binned", "ocio"},
                  "batch");
    BatchRequest r;
    r.input = input;
    r.output = output;
    r.scene = scene;
    // Each keyword, when given, replaces the request's default.
    auto set = [&](const char* key, auto& into) {
        if (auto v = argument(kwargs, key)) into = v.cast<std::remove_reference_t<decltype(into)>>();
    };
    set("preview", r.preview);
    set("contact_sheet", r.contact_sheet);
    set("frames", r.frames);
    set("camera", r.camera);
    set("cameras", r.cameras);
    set("device", r.device);
    set("overwrite_input", r.overwrite_input);
    set("force", r.force);
    set("resume", r.resume);
    set("keep_going", r.keep_going);
    set("binned", r.binned);
    set("threads", r.exr_threads);
    set("queue", r.queue_depth);
    set("workers", r.composite_workers);
    set("extra_inputs", r.extra_inputs);
    set("ocio", r.ocio_config);
    auto passes = argument(kwargs, "passes");
    r.pass_files = passFiles(passes ? passes : py::none());
    if (auto v = argument(kwargs, "shard")) r.shard = parseShard(v.cast<std::string>());
    r.shard_from_environment = false;  // a script decides its own shard (shard="I/N")
    r.mapping = mappingOptions(kwargs);
    if (auto v = argument(kwargs, "pixel_filter")) {  // "auto" (the default) and "auto:fast" choose per frame
        const std::string text = v.cast<std::string>();
        r.pixel_filter_fast = text == "auto:fast";
        if (text != "auto" && !r.pixel_filter_fast) r.pixel_filter = parsePixelFilter(text, "pixel_filter");
    }

    auto progress = std::make_unique<ProgressCallback>(argument(kwargs, "progress"));
    BatchReport report;
    {
        py::gil_scoped_release release;
        report = runBatch(r, progress.get());
        progress.reset();
    }
    py::dict d;
    d["frames"] = report.plan.frames;
    d["written"] = report.progress.written;
    d["skipped"] = report.progress.skipped;
    d["failed"] = report.progress.failed;
    d["elapsed_s"] = report.progress.elapsed_s;
    d["devices"] = report.devices;
    d["camera_source"] = report.camera_source;
    d["warnings"] = report.warnings;
    py::list failures;
    for (const FrameResult& f : report.failures) failures.append(frameResultDict(f));
    d["failures"] = failures;
    d["chunks_copied"] = report.chunks.copied;
    d["chunks_reencoded"] = report.chunks.reencoded;
    d["contact_sheet"] = report.contact_sheet;
    return d;
}

}  // namespace

void bindBatch(py::module_& m) {
    m.def("batch", &batch, py::arg("input"), py::arg("output"), py::arg("scene"),
          "Composites `scene` (a JSON path) into every frame of the `input` pattern (frame.####.exr), "
          "writing `output` (a pattern or a folder), as `decalcomp batch` does. Keyword arguments are the "
          "CLI's flags (frames='1-48', passes={'depth': 'Z.####.exr'}, keep_going=True, progress=callable...). "
          "Returns the report as a dict; without keep_going the first failing frame raises.");
}

}  // namespace decalcomp::python
