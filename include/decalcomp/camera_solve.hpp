#pragma once
// A camera solved from a frame's own passes when no header or sidecar camera exists: every valid
// pixel's world position (the Position plane) must project onto that pixel's centre.
#include <cstddef>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

struct CameraSolveOptions {
    double max_rms_px = 0.5;              // refuse when the inliers' RMS reprojection error is larger
    double outlier_px = 1.0;              // pixels further off than this are left out of the final fit
    double max_outlier_fraction = 0.10;   // refuse when more valid pixels than this are outliers
    std::size_t max_fit_points = 50000;   // the fit uses an even subset of at most this many pixels
};

struct CameraSolveReport {
    bool orthographic = false;
    bool mirrored = false;       // the world is left-handed as seen from the camera (det R = -1)
    std::size_t points = 0;      // valid pixels (finite position, and depth not background)
    std::size_t outliers = 0;    // valid pixels off by more than outlier_px (antialiased edges)
    double rms_px = 0.0, max_px = 0.0;          // reprojection error over the inliers
    double rms_all_px = 0.0, max_all_px = 0.0;  // over every valid pixel
    double near_plane = 0.0, far_plane = 0.0;
    std::string near_far_rule;   // how near/far were chosen (docs/conventions.md)
    std::vector<std::string> notes;

    std::string summary() const;  // "perspective, RMS 0.0012 px, max 0.0040 px over 61234 pixels"
};

// Normalised 3x4 DLT over pixel centres (Hartley normalisation of both point sets), refined by
// reweighting to the geometric reprojection error with outlier rounds; an affine fit decides
// orthographic cameras. The result is decomposed into a (possibly mirrored) rigid world_to_camera
// and an OpenGL projection whose near/far come from the depth range (ndc depth: fitted to the
// depth pass). Throws Error(Input) starting with `label` when there are fewer than 12 valid pixels,
// the points are degenerate, or the residual is too large (the message gives it).
Camera solveCamera(const GBuffer& gbuffer, const std::string& label, CameraSolveReport* report = nullptr,
                   const CameraSolveOptions& options = {});

// Reprojection error of a camera against the position pass (pixels), over valid pixels.
struct Reprojection {
    std::size_t points = 0;
    double rms_px = 0.0, max_px = 0.0;
};
Reprojection reprojectionError(const GBuffer& gbuffer, const Camera& camera);

}  // namespace decalcomp
