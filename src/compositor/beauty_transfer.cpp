#include "compositor/beauty_transfer.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "compositor/surface_planes.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

// As the surface groups: packing is memory traffic, spread over the cores for large frames.
constexpr std::ptrdiff_t kParallelPixels = 1 << 16;

// The sum of the summed terms, packed RGB: the first copied, the others added plane by plane (a
// loop the compiler vectorizes, where one over the terms per float did not).
void packSummedTerms(const BeautyPlanes& planes, float* out) {
    const auto floats = std::ptrdiff_t(planes.beauty.samples.size());
    parallelCopy(out, planes.light[0].samples.data(), {0, std::size_t(floats)});
    for (int t = 1; t < planes.summed_terms; ++t) {
        const float* term = planes.light[std::size_t(t)].samples.data();
#pragma omp parallel for simd schedule(static) if (floats >= 3 * kParallelPixels)
        for (std::ptrdiff_t i = 0; i < floats; ++i) out[i] += term[i];
    }
}

}  // namespace

bool foldsLightTerms(const BeautyPlanes& planes, bool filtered) {
    return planes.divided && !planes.relight && !filtered;
}

std::size_t deviceLightTerms(const BeautyPlanes& planes, bool fold) {
    if (!fold) return planes.light.size();
    return planes.summed_terms > 0 ? 1 : 0;
}

void setBeautyParams(cl_types::DcFrame& params, const BeautyPlanes* planes, bool fold) {
    params.beauty = planes ? 1 : 0;
    params.light_terms = planes ? int(deviceLightTerms(*planes, fold)) : 0;
    params.direct_terms = planes && !fold ? planes->direct_terms : 0;
    params.summed_terms = planes ? (fold ? params.light_terms : planes->summed_terms) : 0;
    params.light_divided = planes && !planes->divided ? 0 : 1;
    params.beauty_emission = planes && planes->emission ? 1 : 0;
    params.relight = planes && planes->relight ? 1 : 0;
    for (int c = 0; c < 4; ++c) params.light_fit[c] = planes ? planes->light_fit[c] : 0.0f;
}

void checkBeautyPlanes(const BeautyPlanes& planes, std::size_t pixels) {
    auto check = [&](const Plane& plane, const std::string& what) {
        if (plane.components != 3 || plane.samples.size() != pixels * 3)
            throw inputError(
                fmt::format("beauty update: the {} plane does not match the frame ({} pixels, RGB)", what, pixels));
    };
    check(planes.beauty, "beauty");
    for (std::size_t t = 0; t < planes.light.size(); ++t) check(planes.light[t], fmt::format("light term {}", t));
    if (planes.direct_terms < 0 || planes.summed_terms < planes.direct_terms ||
        planes.summed_terms > int(planes.light.size()))
        throw inputError("beauty update: direct and summed term counts out of range");
}

void packLightTerms(const BeautyPlanes& planes, bool fold, float* light) {
    const std::size_t floats = planes.beauty.samples.size();
    if (fold) {
        if (planes.summed_terms > 0) packSummedTerms(planes, light);
        return;
    }
    for (std::size_t t = 0; t < planes.light.size(); ++t)
        parallelCopy(light + t * floats, planes.light[t].samples.data(), {0, floats});
}

void unpackBeautyPlanes(BeautyPlanes& planes, int width, int height, const BeautyChangeTiles& where,
                        const float* changes, const float* light) {
    float* beauty = planes.beauty.samples.data();
#pragma omp parallel for schedule(static) if (std::ptrdiff_t(width) * height >= kParallelPixels)
    for (int y = 0; y < height; ++y)
        for (int x0 = 0; x0 < width; x0 += DC_TILE_SIZE) {
            if (where.tile_offsets) {
                const int tile = (y / DC_TILE_SIZE) * where.tiles_x + x0 / DC_TILE_SIZE;
                if (where.tile_offsets[tile + 1] <= where.tile_offsets[tile]) continue;
            } else if (where.decals <= 0) {
                continue;
            }
            const std::size_t row = std::size_t(y) * std::size_t(width);
            for (std::size_t i = row + std::size_t(x0); i < row + std::size_t(std::min(x0 + DC_TILE_SIZE, width));
                 ++i) {
                const float* c = changes + 3 * i;
                if (c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f) continue;
                for (int k = 0; k < 3; ++k) beauty[3 * i + std::size_t(k)] += c[k];
            }
        }
    if (!planes.lightRewritten()) return;
    const std::size_t floats = planes.beauty.samples.size();
    for (std::size_t t = 0; t < planes.light.size(); ++t)
        parallelCopy(planes.light[t].samples.data(), light + t * floats, {0, floats});
}

}  // namespace decalcomp
