// Contact sheets: thumbnails filtered down by OpenImageIO, tiled into one sRGB PNG.
#include "decalcomp/contact_sheet.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "decalcomp/error.hpp"
#include "decalcomp/temporary_files.hpp"
#include "decalcomp/textures.hpp"
#include "images/image_codecs.hpp"

namespace decalcomp {

namespace {

constexpr int kGap = 4;
constexpr unsigned char kEmptyCell = 64;  // grey: a frame without a thumbnail
constexpr unsigned char kBorder = 0;

}  // namespace

Thumbnail makeThumbnail(const GBuffer& gbuffer, int long_side) {
    const int w = gbuffer.width, h = gbuffer.height;
    Thumbnail thumb;
    const auto albedo = gbuffer.planes.find(Attribute::Albedo);
    if (w <= 0 || h <= 0 || albedo == gbuffer.planes.end()) return thumb;
    const Plane& plane = albedo->second;
    std::vector<float> rgb(std::size_t(w) * h * 3, 0.0f);
    for (std::size_t p = 0; p < std::size_t(w) * h; ++p)
        for (int c = 0; c < std::min(3, plane.components); ++c) {
            const float v = plane.at(p, c);
            rgb[p * 3 + c] = std::isfinite(v) ? v : 0.0f;
        }
    const double scale = std::min(1.0, double(std::max(1, long_side)) / std::max(w, h));
    thumb.width = std::max(1, int(std::lround(w * scale)));
    thumb.height = std::max(1, int(std::lround(h * scale)));
    // Filtered in linear light (the albedo is scene-linear), encoded to sRGB afterwards.
    const std::vector<float> linear = scale < 1.0 ? images::imageCodecs(ErrorKind::Output, "contact sheet thumbnail")
                                                        .resize(rgb, w, h, 3, thumb.width, thumb.height)
                                                  : rgb;
    thumb.rgb.resize(linear.size());
    for (std::size_t i = 0; i < linear.size(); ++i) thumb.rgb[i] = linearToSrgbByte(linear[i]);
    return thumb;
}

void ContactSheet::write(const std::string& path) const {
    int cell_w = 1, cell_h = 1;
    for (const auto& [position, thumb] : cells_) cell_w = std::max(cell_w, thumb.width), cell_h = std::max(cell_h, thumb.height);
    const int frames = std::max(frames_, 1);
    const int columns = int(std::ceil(std::sqrt(double(frames))));
    const int rows = (frames + columns - 1) / columns;
    const int out_w = columns * cell_w + (columns + 1) * kGap, out_h = rows * cell_h + (rows + 1) * kGap;
    std::vector<unsigned char> pixels(std::size_t(out_w) * out_h * 3, kBorder);
    for (int i = 0; i < frames; ++i) {
        const int x0 = kGap + (i % columns) * (cell_w + kGap), y0 = kGap + (i / columns) * (cell_h + kGap);
        const auto cell = cells_.find(std::size_t(i));
        for (int y = 0; y < cell_h; ++y)
            for (int x = 0; x < cell_w; ++x)
                for (int c = 0; c < 3; ++c) {
                    const bool inside = cell != cells_.end() && x < cell->second.width && y < cell->second.height;
                    pixels[(std::size_t(y0 + y) * out_w + x0 + x) * 3 + c] =
                        inside ? cell->second.rgb[(std::size_t(y) * cell->second.width + x) * 3 + c]
                               : (cell == cells_.end() ? kEmptyCell : kBorder);
                }
    }
    const std::string tmp = temporaryPathFor(path);
    const std::string opening_name = createTemporary(tmp, path);
    const images::Codecs& codecs = images::imageCodecs(ErrorKind::Output, path);
    if (const std::string why = codecs.write(opening_name, images::png8(out_w, out_h, 3, pixels.data()));
        !why.empty()) {
        discardTemporary(tmp);
        throw outputError(fmt::format("{}: cannot write the contact sheet: {}", path, why));
    }
    commitTemporaries({{tmp, path}});
}

std::string contactSheetPath(const std::string& path, int shard_index, int shard_count) {
    if (shard_count <= 1) return path;
    const std::filesystem::path p(path);
    return (p.parent_path() / fmt::format("{}.shard-{}-of-{}{}", p.stem().string(), shard_index, shard_count,
                                          p.extension().string()))
        .string();
}

}  // namespace decalcomp
