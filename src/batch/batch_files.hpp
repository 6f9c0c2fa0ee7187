#pragma once
// The files of a batch's frames: what each frame reads, where its outputs go, whether it is done
// (--resume), and the checks and clean-up done once before the frames start.
#include <filesystem>
#include <string>
#include <vector>

#include "decalcomp/batch.hpp"
#include "decalcomp/frame.hpp"
#include "decalcomp/frame_cameras.hpp"
#include "decalcomp/scene.hpp"

namespace decalcomp::batch {

// A pattern's path for the frame; a path without a frame token names the same file every frame.
std::string pathAt(const std::string& pattern_or_path, int frame);

// The frame's EXR inputs: positional files and --pass files.
FrameSources frameSources(const BatchRequest& request, const BatchPlan& plan, int frame);

// The files a frame's outputs may be: the pattern's path, or for a folder each of its input
// files' names there (which of them change is known only once the frame's channels are mapped).
std::vector<std::filesystem::path> candidateOutputs(const BatchRequest& request, const BatchPlan& plan, int frame);

// A frame is done when an output exists: the outputs of a frame are renamed into place together,
// after all of them are complete.
bool frameDone(const BatchRequest& request, const BatchPlan& plan, int frame);

// Before any frame starts (without --keep-going): every input of every frame still to do exists
// (positional and --pass files, camera sidecars, a camera in the per-frame cameras file). Throws
// Error(Input) naming the first missing file and how many more are missing, before anything is
// written.
void requireRangeInputs(const BatchRequest& request, const BatchPlan& plan, const FrameCameras& cameras);

// Before any frame starts: the contact sheet `sheet` has a .png name and is none of the files the
// batch reads or writes (any frame's inputs, --pass files, outputs or previews, the scene and its
// textures and meshes, camera files, profiles, the OpenColorIO config), compared as pipeline.hpp's
// sameFile does. Error(Usage).
void checkContactSheet(const BatchRequest& request, const BatchPlan& plan, const DecalScene& scene,
                       const std::string& sheet);

// Creates the folders of every frame's outputs and previews (and the contact sheet's); Error(Output) when one cannot be.
void createOutputFolders(const BatchRequest& request, const BatchPlan& plan);

// How many frames may be between the batch's reader and its writer: enough for `queue_depth`
// frames to wait between each pair of stages and for every worker to hold one, but never more
// than the temporaries their encoded outputs hold at once can keep (kMaxLiveTemporaries; one is
// left for the contact sheet): a frame holds them from its encoding to its turn to be renamed.
int framesInFlight(const BatchRequest& request, int workers);

// Temporaries (".NAME.tmp-PID-N", decalcomp/temporary_files.hpp) that a killed run left for this
// plan's outputs and previews are removed; another shard's are left alone.
void removeStaleTemporaries(const BatchRequest& request, const BatchPlan& plan);

}  // namespace decalcomp::batch
