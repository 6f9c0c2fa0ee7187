#pragma once
// The image files decalcomp reads and writes besides its EXR frames (decal textures, previews,
// contact sheets, baked layers) and OpenColorIO configs, all through OpenImageIO. Debian's
// OpenImageIO pulls in about 250 shared libraries (FFmpeg, OpenCV, GDAL...) whose loading cost
// every process about 0.4 s, so OpenImageIO lives in a module, decalcomp-images.so, loaded the
// first time a program needs it (docs/decisions.md). Only plain types cross this interface.
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "decalcomp/error.hpp"

namespace decalcomp::images {

// Changes whenever anything below does: a module from another build is refused, not misread.
inline constexpr int kCodecsVersion = 1;

// How samples are read or written.
enum class Sample { UInt8, UInt16, Float };

struct ImageHeader {
    std::string format;  // OpenImageIO's name: "png", "openexr", "tiff"...
    int width = 0, height = 0, depth = 1, channels = 0;
    bool deep = false;
    // The stored samples: UInt8 and UInt16 as they are; any other type reads as Float, with
    // `integer` set when the file stores integers (they arrive normalised to [0, 1]).
    Sample stored = Sample::Float;
    bool integer = false;
    int bytes_per_sample = 4;
    int alpha_channel = -1;  // -1: the file names none
    std::vector<std::string> channel_names;
};

class ImageReader {
public:
    virtual ~ImageReader() = default;
    virtual const ImageHeader& header() const = 0;
    // A string attribute of the header ("" when absent).
    virtual std::string stringAttribute(const std::string& name) const = 0;
    // Every channel of the image, interleaved, as `as` into `pixels` (width * height * channels
    // values); "" or the reason it failed, on one line.
    virtual std::string read(Sample as, void* pixels) = 0;
};

struct ImageToWrite {
    std::string format;  // "png", "openexr"
    int width = 0, height = 0, channels = 0;
    Sample sample = Sample::UInt8;                                // of `pixels`, and of the file
    const void* pixels = nullptr;                                 // interleaved
    std::vector<std::string> channel_names;                       // empty: the format's defaults
    int alpha_channel = -1;                                       // -1: the format's default for the channel count
    bool straight_alpha = false;                                  // the colour is not premultiplied: write it as it is
    std::vector<std::pair<std::string, std::string>> attributes;  // header strings ("compression": "zip")
};

// An 8-bit PNG of interleaved channels (previews, contact sheets, bake previews).
inline ImageToWrite png8(int width, int height, int channels, const void* pixels) {
    ImageToWrite png;
    png.format = "png";
    png.width = width;
    png.height = height;
    png.channels = channels;
    png.pixels = pixels;
    return png;
}

// An OpenColorIO config.
class ColourConfigFile {
public:
    virtual ~ColourConfigFile() = default;
    virtual std::vector<std::string> spaceNames() const = 0;
    // The RGB of `count` straight RGBA float texels from `from` to `to` in place, alpha kept;
    // "" or the reason OpenColorIO gave, on one line.
    virtual std::string convert(float* rgba, std::size_t count, const std::string& from,
                                const std::string& to) const = 0;
};

class Codecs {
public:
    virtual ~Codecs() = default;
    // The image at `path` (its first subimage); nullptr with `error` set when it cannot be opened.
    // `straight_alpha`: the stored colour as it is, never divided or multiplied by alpha.
    virtual std::unique_ptr<ImageReader> open(const std::string& path, bool straight_alpha,
                                              std::string& error) const = 0;
    // "" or the reason writing failed (a file that failed may be left: callers write temporaries).
    virtual std::string write(const std::string& path, const ImageToWrite& image) const = 0;
    // Interleaved float `channels` of width x height filtered to new_width x new_height
    // (OpenImageIO's default filter for the ratio).
    virtual std::vector<float> resize(const std::vector<float>& pixels, int width, int height, int channels,
                                      int new_width, int new_height) const = 0;
    // nullptr with `error` set when the config cannot be read or defines no colour space.
    virtual std::unique_ptr<ColourConfigFile> openColourConfig(const std::string& path, std::string& error) const = 0;
};

// The module's codecs, loaded on the first call (thread-safe). When it cannot be loaded, throws
// Error(`kind`) naming what it tried and `needed_for` ("texture plate.png").
const Codecs& imageCodecs(ErrorKind kind, const std::string& needed_for);

}  // namespace decalcomp::images

// What the module exports (C names: looked up with dlsym).
extern "C" {
int decalcomp_image_codecs_version();
const decalcomp::images::Codecs* decalcomp_image_codecs();
}
