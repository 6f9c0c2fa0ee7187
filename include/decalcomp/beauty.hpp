#pragma once
// The beauty follows the decals: the renderer's light passes, as a profile declares them, and the
// planes the shading kernel rebuilds the beauty from (docs/profiles.md "Beauty").
#include <optional>
#include <string>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/gbuffer.hpp"

namespace decalcomp {

// --beauty: auto rebuilds when the passes are there, on requires them, off leaves the beauty.
enum class BeautyMode { Auto, Off, On };
const char* beautyModeName(BeautyMode mode);  // "auto", "off", "on"
std::optional<BeautyMode> beautyModeFromName(const std::string& name);

struct BeautyOptions {
    BeautyMode mode = BeautyMode::Auto;
    // Opt-in approximation for normal decals: the direct light is scaled by the ratio of a Lambert
    // fit (light direction estimated from the pass) with the new and the old normal.
    bool relight = false;
};

// One RGB pass of a lobe: its spellings (component-group patterns such as
// "{layer}.DiffDir.{R,G,B}") in preference order, one per naming generation.
struct BeautyTerm {
    std::string role;  // "direct", "indirect", "total", "colour", or the added pass's name
    std::vector<std::string> spellings;
};

// A BSDF lobe: colour * (direct + indirect) is its share of the beauty.
struct BeautyLobe {
    std::string name;                 // "diffuse", "glossy", "transmission", ...
    bool follows_albedo = false;      // its colour is the albedo attribute (decals change it)
    std::optional<BeautyTerm> colour; // a colour pass decals do not change (GlossCol); info only
    std::vector<BeautyTerm> terms;    // direct and indirect light; "total" terms (Arnold's diffuse) are
                                      // rewritten with them but not summed into the beauty
};

// What a renderer profile says about its beauty and light passes.
struct BeautyModel {
    std::vector<std::string> beauty;  // spellings of the beauty's RGB (alpha is never touched)
    bool divided = true;              // light passes divided by their colour (Blender); else multiplied
    std::vector<BeautyLobe> lobes;
    std::vector<BeautyTerm> added;    // passes added as they are (emission, environment, volume)
    bool declared() const { return !beauty.empty(); }
};

// The planes the shading kernel updates, over the G-buffer's window (3 components each).
struct BeautyPlanes {
    Plane beauty;              // RGB
    std::vector<Plane> light;  // the albedo lobe's terms: direct ones first, then indirect, then totals
    int direct_terms = 0;      // light[0, direct_terms) is direct light (relight scales it)
    int summed_terms = 0;      // light[0, summed_terms) adds up in the beauty
    bool divided = true;       // as BeautyModel::divided; multiplied terms are rewritten too
    bool emission = false;     // emission changes add to the beauty
    bool relight = false;      // scale direct light by the Lambert ratio of new and old normal
    float light_fit[4] = {0, 0, 0, 0};  // direct light ~ max(0, fit.w + dot(fit.xyz, world normal))
    bool lightRewritten() const { return !divided || relight; }
};

// Direct light fitted from a pass against the world normals, for the relight approximation:
// luminance(light) ~ w + dot(c, n) in the least-squares sense over lit pixels (every `step`-th).
// Multiplied light (!divided) is divided by the frame's albedo first; the frame's normals are decoded
// to world space with `camera`. Zero when too few pixels are lit.
struct LightFit {
    float c[3] = {0, 0, 0};
    float w = 0;
    std::size_t pixels = 0;  // pixels the fit used
    double rms = 0;          // of the fit's residual, over those pixels
};
LightFit fitDirectLight(const std::vector<const Plane*>& direct, bool divided, const GBuffer& frame,
                        const Camera& camera, std::size_t step = 1);

}  // namespace decalcomp
