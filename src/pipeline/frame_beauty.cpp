// The beauty step of a frame: finding the profile's light passes, deciding, reading the planes,
// storing them back (decalcomp/frame_beauty.hpp).
#include "decalcomp/frame_beauty.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "decalcomp/error.hpp"
#include "decalcomp/gbuffer_exr.hpp"
#include "decalcomp/profiles.hpp"

namespace decalcomp {

namespace {

using ChannelIndex = std::map<std::string, ChannelRef>;

ChannelIndex indexChannels(const std::vector<ExrImage>& files) {
    ChannelIndex index;
    for (std::size_t f = 0; f < files.size(); ++f)
        for (std::size_t p = 0; p < files[f].parts.size(); ++p)
            for (std::size_t c = 0; c < files[f].parts[p].channels.size(); ++c)
                index.emplace(files[f].parts[p].channels[c].qualified, ChannelRef{int(p), int(c), int(f)});
    return index;
}

std::string withLayer(std::string pattern, const std::string& layer) {
    const auto at = pattern.find("{layer}");
    if (at != std::string::npos) pattern.replace(at, 7, layer);
    return pattern;
}

// The first spelling whose three channels all exist.
std::optional<FoundPass> findTerm(const ChannelIndex& index, const BeautyTerm& term, const std::string& layer,
                                  const std::string& lobe) {
    for (const std::string& spelling : term.spellings) {
        if (spelling.find("{layer}") != std::string::npos && layer.empty()) continue;
        FoundPass found{term.role, lobe, withLayer(spelling, layer), {}};
        for (const std::string& channel : expandChannelPattern(found.name)) {
            const auto at = index.find(channel);
            if (at == index.end()) break;
            found.refs.push_back(at->second);
        }
        if (found.refs.size() == 3) return found;
    }
    return std::nullopt;
}

// "DiffDir (ViewLayer.DiffDir.{R,G,B})": the pass by its first spelling.
std::string missingName(const BeautyTerm& term, const std::string& layer, const std::string& lobe) {
    return fmt::format("{} {} ({})", lobe, term.role, withLayer(term.spellings.front(), layer));
}

const ChannelProfile* profileNamed(const std::vector<ChannelProfile>& profiles, const std::string& name) {
    for (const ChannelProfile& p : profiles)
        if (p.name == name) return &p;
    return nullptr;
}

// Stores an RGB plane into three channels through the attribute writer, so the channel rules
// (sample types, bit-exact untouched pixels, changed chunks) are the same as for the attributes:
// a copy of the mapping lends the refs to one attribute slot.
std::size_t storeRgb(std::vector<ExrImage>& files, const ChannelMapping& mapping, const FoundPass& pass,
                     const Plane& plane) {
    ChannelMapping lent = mapping;
    lent.attributes[Attribute::Emission] = pass.refs;
    return storeAttribute(files, lent, Attribute::Emission, plane);
}

bool changesBeyondAlbedo(Attribute a) {
    return a == Attribute::Normal || a == Attribute::Roughness || a == Attribute::Metallic ||
           a == Attribute::AmbientOcclusion;
}

}  // namespace

const char* beautyModeName(BeautyMode mode) {
    switch (mode) {
        case BeautyMode::Auto: return "auto";
        case BeautyMode::Off: return "off";
        case BeautyMode::On: return "on";
    }
    return "auto";
}

std::optional<BeautyMode> beautyModeFromName(const std::string& name) {
    for (BeautyMode m : {BeautyMode::Auto, BeautyMode::Off, BeautyMode::On})
        if (name == beautyModeName(m)) return m;
    return std::nullopt;
}

std::vector<std::string> BeautyPasses::describe() const {
    std::vector<std::string> lines;
    if (!model.declared()) {
        lines.push_back(fmt::format("profile {} declares no light passes: the beauty is not rebuilt", profile));
        return lines;
    }
    lines.push_back(fmt::format("model: {} ({} light: beauty = sum of colour x (direct + indirect){} + added passes)",
                                profile, model.divided ? "divided" : "multiplied",
                                model.divided ? "" : " / colour"));
    lines.push_back(beauty ? fmt::format("beauty: {}", beauty->name) : "beauty: not found");
    std::vector<std::string> terms;
    for (const FoundPass& p : light) terms.push_back(fmt::format("{} {}", p.role, p.name));
    lines.push_back(fmt::format("albedo lobe: {}", terms.empty() ? "no light passes found" : fmt::format("{}", fmt::join(terms, ", "))));
    if (!missing.empty()) lines.push_back(fmt::format("missing: {}", fmt::join(missing, ", ")));
    std::vector<std::string> other;
    for (const FoundPass& p : others) other.push_back(p.lobe.empty() ? fmt::format("{} {}", p.role, p.name)
                                                                    : fmt::format("{} {} {}", p.lobe, p.role, p.name));
    if (!other.empty()) lines.push_back(fmt::format("unchanged by decals: {}", fmt::join(other, ", ")));
    lines.push_back(complete() ? "rebuild: yes (--beauty auto)" : "rebuild: no (passes missing)");
    return lines;
}

BeautyPasses findBeautyPasses(const std::vector<ExrImage>& files, const ChannelMapping& mapping,
                              const MappingOptions& options) {
    BeautyPasses passes;
    passes.profile = mapping.profile;
    const std::vector<ChannelProfile> profiles = profileSet(options.profile_files);
    if (const ChannelProfile* profile = profileNamed(profiles, mapping.profile)) passes.model = profile->beauty;
    if (!passes.model.declared()) return passes;
    const ChannelIndex index = indexChannels(files);
    const std::string& layer = mapping.layer;
    passes.beauty = findTerm(index, {"beauty", passes.model.beauty}, layer, "");
    for (const BeautyLobe& lobe : passes.model.lobes) {
        for (const BeautyTerm& term : lobe.terms) {
            std::optional<FoundPass> found = findTerm(index, term, layer, lobe.name);
            if (lobe.follows_albedo) {
                if (found) passes.light.push_back(std::move(*found));
                else if (term.role != "total") passes.missing.push_back(missingName(term, layer, lobe.name));
            } else if (found) {
                passes.others.push_back(std::move(*found));
            }
        }
        if (lobe.colour)
            if (auto found = findTerm(index, *lobe.colour, layer, lobe.name)) passes.others.push_back(std::move(*found));
    }
    // direct terms first, then indirect, then totals (the kernel's order)
    auto rank = [](const FoundPass& p) { return p.role == "direct" ? 0 : p.role == "indirect" ? 1 : 2; };
    std::stable_sort(passes.light.begin(), passes.light.end(),
                     [&](const FoundPass& a, const FoundPass& b) { return rank(a) < rank(b); });
    for (const BeautyTerm& term : passes.model.added)
        if (auto found = findTerm(index, term, layer, "")) passes.others.push_back(std::move(*found));
    return passes;
}

void FrameBeauty::prepare(const std::vector<ExrImage>& files, const ChannelMapping& mapping,
                          const MappingOptions& mapping_options, const BeautyOptions& options,
                          const std::vector<Attribute>& attributes, const std::map<int, std::string>& outputs,
                          const std::string& label, std::vector<std::string>& warnings) {
    report_ = {};
    report_.mode = options.mode;
    rebuild_ = false;
    if (options.mode == BeautyMode::Off) return;
    passes_ = findBeautyPasses(files, mapping, mapping_options);
    const bool on = options.mode == BeautyMode::On;
    if (!passes_.model.declared()) {
        if (on)
            throw inputError(fmt::format("{}: --beauty on: profile {} declares no light passes (docs/profiles.md "
                                         "\"Beauty\"; a --profile-file can add them)",
                                         label, passes_.profile));
        return;
    }
    if (!passes_.beauty) {
        if (on)
            throw inputError(fmt::format("{}: --beauty on: no beauty channels ({}) found", label,
                                         withLayer(passes_.model.beauty.front(), mapping.layer)));
        return;  // no beauty: nothing can contradict the decals
    }
    if (!passes_.complete()) {
        const std::string missing =
            passes_.missing.empty() ? std::string("the albedo lobe's light passes") : fmt::format("{}", fmt::join(passes_.missing, ", "));
        if (on) throw inputError(fmt::format("{}: --beauty on: light passes missing: {}", label, missing));
        warnings.push_back(fmt::format("{}: the beauty ({}) is not rebuilt: light passes missing: {}; it still shows "
                                       "the surfaces without the decals (render those passes, or --beauty off)",
                                       label, passes_.beauty->name, missing));
        return;
    }
    int beauty_file = passes_.beauty->refs.front().file;
    bool written = outputs.count(beauty_file) != 0;
    for (const FoundPass& p : passes_.light) written = written && (passes_.model.divided || outputs.count(p.refs.front().file));
    if (!written) {
        const std::string message = fmt::format("{}: the beauty ({}) is not rebuilt: it lives in {}, which this run does "
                                                "not write (it holds no composited attribute)",
                                                label, passes_.beauty->name, files.at(std::size_t(beauty_file)).path);
        if (on) throw inputError("--beauty on: " + message);
        warnings.push_back(message);
        return;
    }
    rebuild_ = true;
    relight_ = options.relight && std::count(attributes.begin(), attributes.end(), Attribute::Normal) > 0 &&
               mapping.attributes.count(Attribute::Normal);
    emission_ = std::count(attributes.begin(), attributes.end(), Attribute::Emission) > 0 &&
                mapping.attributes.count(Attribute::Emission) &&
                std::any_of(passes_.model.added.begin(), passes_.model.added.end(),
                            [](const BeautyTerm& t) { return t.role == "emission"; });
    std::vector<std::string> terms;
    for (const FoundPass& p : passes_.light)
        if (p.role != "total") terms.push_back(p.name);
    report_.summary = fmt::format("rebuilt {} from {} ({}, light {}{}{})", passes_.beauty->name, fmt::join(terms, " + "),
                                  passes_.profile, passes_.model.divided ? "divided by colour" : "multiplied by colour",
                                  emission_ ? ", plus emission changes" : "", relight_ ? ", relit (approximation)" : "");
    std::vector<std::string> ignored;
    for (Attribute a : attributes)
        if (changesBeyondAlbedo(a) && mapping.attributes.count(a) && !(a == Attribute::Normal && relight_))
            ignored.push_back(attributeName(a));
    if (!ignored.empty())
        warnings.push_back(fmt::format(
            "{}: the rebuilt beauty shows albedo and emission changes only: the {} decals do not relight it{}", label,
            fmt::join(ignored, ", "),
            std::count(ignored.begin(), ignored.end(), std::string("normal")) ? " (--relight approximates normal changes)" : ""));
}

void FrameBeauty::read(const std::vector<ExrImage>& files, const ChannelMapping& mapping, const GBuffer& gbuffer,
                       const Camera& camera, bool keep_before) {
    planes_.reset();
    before_.reset();
    if (!rebuild_) return;
    const Imath::Box2i window = frameWindow(files, mapping).data;
    BeautyPlanes planes;
    planes.beauty = readChannelsOnWindow(files, passes_.beauty->refs, window, 0.0f, false, "beauty");
    for (const FoundPass& p : passes_.light) {
        planes.light.push_back(readChannelsOnWindow(files, p.refs, window, 0.0f, false, p.name));
        if (p.role == "direct") ++planes.direct_terms;
        if (p.role != "total") ++planes.summed_terms;
    }
    planes.divided = passes_.model.divided;
    planes.emission = emission_;
    if (relight_) {
        std::vector<const Plane*> direct;
        for (int t = 0; t < planes.direct_terms; ++t) direct.push_back(&planes.light[std::size_t(t)]);
        const LightFit fit = fitDirectLight(direct, planes.divided, gbuffer, camera,
                                            std::max<std::size_t>(1, gbuffer.pixelCount() / 200000));
        report_.fit = fit;
        planes.relight = fit.pixels > 0;
        for (int c = 0; c < 3; ++c) planes.light_fit[c] = fit.c[c];
        planes.light_fit[3] = fit.w;
    }
    if (keep_before) before_ = planes.beauty;
    planes_ = std::move(planes);
}

std::size_t FrameBeauty::store(std::vector<ExrImage>& files, const ChannelMapping& mapping) {
    if (!planes_) return 0;
    std::size_t changed = storeRgb(files, mapping, *passes_.beauty, planes_->beauty);
    if (planes_->lightRewritten())
        for (std::size_t t = 0; t < passes_.light.size(); ++t)
            changed += storeRgb(files, mapping, passes_.light[t], planes_->light[t]);
    report_.rebuilt = true;
    report_.changed_samples = changed;
    return changed;
}

}  // namespace decalcomp
