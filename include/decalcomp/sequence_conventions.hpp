#pragma once
// How a frame's depth and normal passes are read, checked against its geometry and settled, and
// which pixel filter it was rendered with: once per frame for `composite`, once per sequence for
// `batch` (the first frame whose check is conclusive decides for every frame, so a sequence is
// never read two ways).
#include <functional>
#include <mutex>
#include <optional>

#include "decalcomp/camera.hpp"
#include "decalcomp/depth_check.hpp"
#include "decalcomp/channel_mapping.hpp"
#include "decalcomp/gbuffer.hpp"
#include "decalcomp/normal_check.hpp"
#include "decalcomp/pixel_filter.hpp"

namespace decalcomp {

// Checks planar vs radial depth against the position pass and, unless --depth was given, adopts
// the verdict in both the G-buffer and the mapping (with a note).
DepthCheck settleDepthConvention(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera);

// Checks the normal pass's space and encoding against the geometry and, unless --normals was
// given, adopts a clear verdict in both the G-buffer and the mapping (with a note).
NormalCheck settleNormalEncoding(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera);

// The verdicts a sequence settled; safe to share between threads.
class SequenceConventions {
public:
    // Applies the sequence's verdicts to this frame, or runs the checks and keeps the first
    // conclusive verdict for the frames after it. The checks' results go to `depth` / `normals`
    // when they ran on this frame.
    void settle(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera, DepthCheck* depth,
                NormalCheck* normals);

    std::optional<DepthConvention> depth() const;
    std::optional<NormalEncoding> normals() const;

    // The pixel filter settled for the sequence, else `choose()`'s for this frame, which settles it
    // when conclusive: decals never switch between filtered and point-sampled within a shot, and
    // later frames skip the normal-pass scan.
    PixelFilterChoice pixelFilter(const std::function<PixelFilterChoice()>& choose);

private:
    mutable std::mutex mutex_;
    std::optional<DepthConvention> depth_;
    std::optional<NormalEncoding> normals_;
    std::optional<PixelFilterChoice> pixel_filter_;
};

}  // namespace decalcomp
