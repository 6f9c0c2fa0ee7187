// decalcomp::Frame through the library, without the CLI: prepare / composite / writeBack on a
// synthetic frame, the order the steps must come in, refusing to overwrite the input, one depth
// convention per sequence (SequenceConventions), and a ComputeDevice embedded in an OpenCL
// context the host program owns.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "decalcomp/error.hpp"
#include "decalcomp/frame.hpp"
#include "decalcomp/sequence_conventions.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 64, kHeight = 48;

// One generic-named frame (Z, albedo, P, beauty RGBA, camera in the header) and a static scene.
struct SyntheticFrame {
    test::ScratchDir dir;
    std::string input = FramePattern(test::writeSequence(dir.path() / "in", {1}, kWidth, kHeight)).path(1);
    std::string scene_path = test::writeStaticScene(dir.path());
    DecalScene scene = loadScene(scene_path);
};

Frame makeFrame(const std::vector<std::string>& inputs, const std::string& output, bool overwrite_input = false) {
    FrameSources sources;
    sources.inputs = inputs;
    FrameTargets targets;
    targets.output = output;
    targets.overwrite_input = overwrite_input;
    return Frame(std::move(sources), std::move(targets), FrameOptions{});
}

// prepare, composite and write back `input` to `output` on `device`; returns the report.
FrameReport compositeFrame(const std::string& input, const std::string& output, const DecalScene& scene,
                           ComputeDevice& device) {
    Frame frame = makeFrame({input}, output);
    frame.prepare(scene);
    Compositor compositor(device);
    compositor.setScene(scene);
    frame.composite(compositor);
    frame.writeBack();
    return frame.report();
}

std::set<std::string> filesUnder(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir)) names.insert(fs::relative(e.path(), dir).string());
    return names;
}

ErrorKind errorKindOf(const std::function<void()>& step) {
    try {
        step();
    } catch (const Error& e) {
        return e.kind();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not a decalcomp::Error: " << e.what();
        return ErrorKind::Input;
    }
    ADD_FAILURE() << "did not throw";
    return ErrorKind::Input;
}

TEST(Frame, PrepareCompositeWriteBackChangesTheAlbedoLikeTheCompositor) {
    SyntheticFrame s;
    ComputeDevice device("cpu");
    const std::string out = s.dir.file("result.exr");
    Frame frame = makeFrame({s.input}, out);
    frame.prepare(s.scene);
    EXPECT_TRUE(frame.hasDecals());
    EXPECT_EQ(frame.outputs(), (std::map<int, std::string>{{0, out}}));
    EXPECT_FALSE(fs::exists(out)) << "prepare writes nothing";
    EXPECT_EQ(frame.report().mapping.profile, "generic");
    EXPECT_EQ(frame.gbuffer().width, kWidth);

    Compositor compositor(device);
    compositor.setScene(s.scene);
    frame.composite(compositor);
    EXPECT_FALSE(fs::exists(out)) << "composite writes nothing";
    EXPECT_EQ(frame.report().stats.decals, 1);

    const std::vector<std::string> written = frame.writeBack();
    EXPECT_EQ(written, std::vector<std::string>{out});
    EXPECT_EQ(frame.report().outputs, std::vector<std::string>{out});
    ASSERT_TRUE(fs::exists(out));
    const ExrImage result = readExr(out), input = readExr(s.input);
    EXPECT_EQ(test::pixelDifference(result, test::expectedFrame(s.input, s.scene, 1, device)), "");
    // The albedo changed, and nothing else did.
    ASSERT_EQ(result.parts.size(), 1u);
    ASSERT_EQ(result.parts[0].channels.size(), input.parts[0].channels.size());
    std::set<std::string> changed;
    for (std::size_t c = 0; c < input.parts[0].channels.size(); ++c)
        if (result.parts[0].channels[c].bytes != input.parts[0].channels[c].bytes)
            changed.insert(result.parts[0].channels[c].name);
    EXPECT_EQ(changed, (std::set<std::string>{"albedo.R", "albedo.G", "albedo.B"}));
}

TEST(Frame, StepsOutOfOrderThrowAndWriteNothing) {
    SyntheticFrame s;
    ComputeDevice device("cpu");
    Compositor compositor(device);
    compositor.setScene(s.scene);
    const std::string out = s.dir.file("out.exr");
    Frame frame = makeFrame({s.input}, out);
    EXPECT_EQ(errorKindOf([&] { frame.composite(compositor); }), ErrorKind::Usage);
    EXPECT_EQ(errorKindOf([&] { frame.writeBack(); }), ErrorKind::Usage);
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(errorKindOf([] { makeFrame({}, "x.exr"); }), ErrorKind::Usage) << "a frame without inputs";
    // After prepare the same frame composites.
    frame.prepare(s.scene);
    frame.composite(compositor);
    EXPECT_EQ(frame.writeBack(), std::vector<std::string>{out});
    EXPECT_TRUE(fs::exists(out));
}

TEST(Frame, OutputThatIsTheInputIsRefusedInPrepareWithoutOverwriteInput) {
    SyntheticFrame s;
    const std::set<std::string> before = filesUnder(s.dir.path());
    const std::string bytes = test::readFileBytes(s.input);
    Frame frame = makeFrame({s.input}, s.input);
    try {
        frame.prepare(s.scene);
        ADD_FAILURE() << "prepare accepted the input as output";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Usage);
        EXPECT_NE(std::string(e.what()).find("--overwrite-input"), std::string::npos) << e.what();
    }
    EXPECT_EQ(filesUnder(s.dir.path()), before) << "nothing created";
    EXPECT_EQ(test::readFileBytes(s.input), bytes);

    // The same path through another spelling is still the input.
    const std::string other = (s.dir.path() / "in" / "." / fs::path(s.input).filename()).string();
    EXPECT_EQ(errorKindOf([&] { makeFrame({s.input}, other).prepare(s.scene); }), ErrorKind::Usage);

    // Allowed, it replaces the input.
    ComputeDevice device("cpu");
    Frame allowed = makeFrame({s.input}, s.input, /*overwrite_input=*/true);
    allowed.prepare(s.scene);
    Compositor compositor(device);
    compositor.setScene(s.scene);
    allowed.composite(compositor);
    allowed.writeBack();
    EXPECT_NE(test::readFileBytes(s.input), bytes);
    EXPECT_EQ(filesUnder(s.dir.path()), before);
}

// A frame rendered with radial depth; `position` false leaves the P pass out.
std::string writeRadialFrame(const fs::path& dir, const std::string& name, int frame, bool position,
                             DepthConvention depth = DepthConvention::Radial) {
    test::ChannelSamples passes = test::genericPasses(test::renderSequenceFrame(frame, kWidth, kHeight, depth));
    if (!position)
        for (const char* c : {"P.X", "P.Y", "P.Z"}) passes.erase(c);
    const std::string path = (dir / name).string();
    test::writeFloatExr(path, kWidth, kHeight, passes, test::sequenceCamera(frame, kWidth, kHeight));
    return path;
}

// The pixel filter settles like the conventions: frames that cannot tell (no sharp turn in their
// normals) neither settle it nor are held to a guess; the first that can decides for the rest,
// which then skip the scan of their normal pass.
TEST(Frame, SequenceSettlesThePixelFilterOnTheFirstConclusiveFrame) {
    SequenceConventions sequence;
    int scans = 0;
    const auto frameSaying = [&](const std::string& filter, bool conclusive) {
        return [&scans, filter, conclusive] {
            ++scans;
            return PixelFilterChoice{parsePixelFilter(filter, ""), "frame saying " + filter, conclusive};
        };
    };
    const PixelFilterChoice unsure = sequence.pixelFilter(frameSaying("blackman-harris:3", false));
    EXPECT_EQ(unsure.filter.spelling(), "blackman-harris:3");
    const PixelFilterChoice first = sequence.pixelFilter(frameSaying("none", true));
    EXPECT_EQ(first.filter.spelling(), "none");
    EXPECT_EQ(scans, 2);
    for (const char* later : {"gaussian:2", "box:1"}) {
        const PixelFilterChoice settled = sequence.pixelFilter(frameSaying(later, true));
        EXPECT_EQ(settled.filter.spelling(), "none") << later;
        EXPECT_EQ(settled.source, "frame saying none");
    }
    EXPECT_EQ(scans, 2) << "settled frames scan nothing";
}

TEST(Frame, SequenceConventionsSettleOnceForTheSequence) {
    SyntheticFrame s;
    const std::string radial = writeRadialFrame(s.dir.path(), "radial.exr", 1, true);
    const std::string no_position = writeRadialFrame(s.dir.path(), "no_position.exr", 2, false);
    const std::string planar = writeRadialFrame(s.dir.path(), "planar.exr", 3, true, DepthConvention::Planar);

    // Alone, a frame without a position pass keeps the profile's planar default; one with it is checked.
    Frame alone = makeFrame({no_position}, s.dir.file("alone.exr"));
    alone.prepare(s.scene);
    EXPECT_EQ(alone.gbuffer().depth_convention, DepthConvention::Planar);
    Frame checked = makeFrame({radial}, s.dir.file("checked.exr"));
    checked.prepare(s.scene);
    ASSERT_TRUE(checked.report().depth_check.verdict) << checked.report().depth_check.summary();
    EXPECT_EQ(*checked.report().depth_check.verdict, DepthConvention::Radial);

    SequenceConventions sequence;
    EXPECT_FALSE(sequence.depth());
    Frame first = makeFrame({radial}, s.dir.file("first.exr"));
    first.prepare(s.scene, &sequence);
    EXPECT_TRUE(first.report().depth_check.performed);
    EXPECT_EQ(first.gbuffer().depth_convention, DepthConvention::Radial);
    ASSERT_TRUE(sequence.depth());
    EXPECT_EQ(*sequence.depth(), DepthConvention::Radial);

    // The second frame has nothing to check against: it takes the first frame's verdict.
    Frame second = makeFrame({no_position}, s.dir.file("second.exr"));
    second.prepare(s.scene, &sequence);
    EXPECT_FALSE(second.report().depth_check.performed);
    EXPECT_EQ(second.gbuffer().depth_convention, DepthConvention::Radial);
    EXPECT_EQ(second.report().mapping.depth_convention, DepthConvention::Radial);

    // Settled once: a later frame is not checked again, whatever its passes would say.
    Frame third = makeFrame({planar}, s.dir.file("third.exr"));
    third.prepare(s.scene, &sequence);
    EXPECT_FALSE(third.report().depth_check.performed);
    EXPECT_EQ(third.gbuffer().depth_convention, DepthConvention::Radial);

    // The frame's composite follows the settled reading: radial differs from planar on frame 2.
    ComputeDevice device("cpu");
    Compositor compositor(device);
    compositor.setScene(s.scene);
    second.composite(compositor);
    alone.composite(compositor);
    EXPECT_NE(second.gbuffer().planes.at(Attribute::Albedo).samples,
              alone.gbuffer().planes.at(Attribute::Albedo).samples);
}

// The host program's own context, device and queue.
struct HostOpenCl {
    DeviceInfo info = selectDevice("cpu");
    cl::Context context{info.device};
    cl::CommandQueue queue;
    explicit HostOpenCl(cl_command_queue_properties properties) : queue(context, info.device, properties) {}
};

TEST(Frame, EmbeddedOpenClObjectsCompositeTheSameBytes) {
    SyntheticFrame s;
    HostOpenCl host(CL_QUEUE_PROFILING_ENABLE);
    ComputeDevice selected("cpu");
    ComputeDevice embedded(host.context, host.info.device, host.queue);
    EXPECT_TRUE(selected.profiling());
    EXPECT_TRUE(embedded.profiling());
    EXPECT_EQ(embedded.info().name, host.info.name);
    EXPECT_EQ(embedded.info().index, host.info.index);
    EXPECT_EQ(embedded.context()(), host.context());
    EXPECT_EQ(embedded.queue()(), host.queue());

    const FrameReport a = compositeFrame(s.input, s.dir.file("selected.exr"), s.scene, selected);
    const FrameReport b = compositeFrame(s.input, s.dir.file("embedded.exr"), s.scene, embedded);
    const ExrImage reference = readExr(s.dir.file("selected.exr"));
    EXPECT_NE(test::pixelDifference(reference, readExr(s.input)), "") << "the decal landed";
    EXPECT_EQ(test::pixelDifference(readExr(s.dir.file("embedded.exr")), reference), "");
    EXPECT_EQ(a.stats.decals, 1);
    EXPECT_EQ(b.stats.decals, 1);
    EXPECT_GT(a.stats.totalKernelMs(), 0.0);
    EXPECT_GT(b.stats.totalKernelMs(), 0.0) << "a profiling queue gives kernel times";
}

TEST(Frame, EmbeddedQueueWithoutProfilingReportsZeroKernelTimes) {
    SyntheticFrame s;
    HostOpenCl host(0);
    ComputeDevice unprofiled(host.context, host.info.device, host.queue);
    EXPECT_FALSE(unprofiled.profiling());
    FrameReport report;
    ASSERT_NO_THROW(report = compositeFrame(s.input, s.dir.file("unprofiled.exr"), s.scene, unprofiled));
    EXPECT_EQ(report.stats.decals, 1) << "it composited";
    EXPECT_EQ(report.stats.totalKernelMs(), 0.0);
    EXPECT_EQ(report.stats.shading_ms, 0.0);
    EXPECT_EQ(report.stats.binning_ms, 0.0);
    EXPECT_EQ(report.stats.tile_bounds_ms, 0.0);
    ComputeDevice selected("cpu");
    compositeFrame(s.input, s.dir.file("selected.exr"), s.scene, selected);
    EXPECT_EQ(test::pixelDifference(readExr(s.dir.file("unprofiled.exr")), readExr(s.dir.file("selected.exr"))), "");
}

}  // namespace
}  // namespace decalcomp
