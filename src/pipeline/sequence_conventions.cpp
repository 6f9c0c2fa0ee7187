#include "decalcomp/sequence_conventions.hpp"

#include <fmt/format.h>

namespace decalcomp {

namespace {

void adoptNormals(GBuffer& gbuffer, ChannelMapping& mapping, const NormalEncoding& encoding) {
    gbuffer.normal_encoding = encoding;
    mapping.normals = encoding;
}

}  // namespace

DepthCheck settleDepthConvention(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera) {
    DepthCheck check = checkDepthConvention(gbuffer, camera);
    mapping.notes.push_back("depth check: " + check.summary());
    if (check.verdict && *check.verdict != gbuffer.depth_convention) {
        if (mapping.depth_convention_explicit) {
            mapping.notes.push_back(fmt::format("depth convention stays {} (explicit --depth) although the position "
                                                "pass suggests {}",
                                                depthConventionName(gbuffer.depth_convention),
                                                depthConventionName(*check.verdict)));
        } else {
            gbuffer.depth_convention = *check.verdict;
            mapping.depth_convention = *check.verdict;
            mapping.notes.push_back(fmt::format("depth convention: {} (checked against the position pass)",
                                                depthConventionName(*check.verdict)));
        }
    }
    return check;
}

NormalCheck settleNormalEncoding(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera) {
    NormalConstraints fixed;
    if (mapping.normal_space_explicit) fixed.space = gbuffer.normal_encoding.space;
    if (mapping.normal_encoding_explicit) fixed.packed = gbuffer.normal_encoding.packed;
    NormalCheck check = checkNormalEncoding(gbuffer, camera, fixed);
    if (!gbuffer.has(Attribute::Normal)) return check;
    mapping.notes.push_back("normal check: " + check.summary());
    const NormalEncoding& current = gbuffer.normal_encoding;
    if (!check.verdict || (check.verdict->space == current.space && check.verdict->packed == current.packed)) return check;
    adoptNormals(gbuffer, mapping, *check.verdict);
    mapping.notes.push_back(fmt::format("normals: {} space, {} (checked against the depth pass)", normalSpaceName(mapping.normals.space),
                                        check.verdict->packed ? "packed" : "signed"));
    return check;
}

void SequenceConventions::settle(GBuffer& gbuffer, ChannelMapping& mapping, const Camera& camera, DepthCheck* depth,
                                 NormalCheck* normals) {
    // The planar/radial check runs until one frame could perform it (or the frames have no
    // position pass to check against); its verdict then holds for the whole sequence.
    if (const std::optional<DepthConvention> settled = this->depth()) {
        gbuffer.depth_convention = *settled;
        mapping.depth_convention = *settled;
    } else {
        const DepthCheck check = settleDepthConvention(gbuffer, mapping, camera);
        if (depth) *depth = check;
        if (check.performed || !gbuffer.has(Attribute::Position)) {
            std::lock_guard lock(mutex_);
            if (!depth_) depth_ = gbuffer.depth_convention;
        }
    }
    if (!gbuffer.has(Attribute::Normal)) return;
    // The first frame whose normals fit one reading clearly settles it for the sequence.
    if (const std::optional<NormalEncoding> settled = this->normals()) {
        adoptNormals(gbuffer, mapping, *settled);
        return;
    }
    const NormalCheck check = settleNormalEncoding(gbuffer, mapping, camera);
    if (normals) *normals = check;
    if (check.verdict) {
        std::lock_guard lock(mutex_);
        if (!normals_) normals_ = gbuffer.normal_encoding;
    }
}

std::optional<DepthConvention> SequenceConventions::depth() const {
    std::lock_guard lock(mutex_);
    return depth_;
}

std::optional<NormalEncoding> SequenceConventions::normals() const {
    std::lock_guard lock(mutex_);
    return normals_;
}

PixelFilterChoice SequenceConventions::pixelFilter(const std::function<PixelFilterChoice()>& choose) {
    {
        std::lock_guard lock(mutex_);
        if (pixel_filter_) return *pixel_filter_;
    }
    const PixelFilterChoice choice = choose();  // outside the lock: it scans the frame's normals
    if (!choice.conclusive) return choice;
    std::lock_guard lock(mutex_);
    if (!pixel_filter_) pixel_filter_ = choice;
    return *pixel_filter_;  // a frame that raced another takes the settled choice too
}

}  // namespace decalcomp
