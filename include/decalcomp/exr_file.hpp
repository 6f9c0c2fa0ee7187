#pragma once
// OpenEXR files kept whole: every part, header and channel, so a frame can be written back with
// the same layout, pixel types, compression and metadata, and only decal-affected channels change.
#include <OpenEXR/ImfHeader.h>

#include <string>
#include <vector>

namespace decalcomp {

enum class SampleType { Uint, Half, Float };

struct ExrChannel {
    std::string name;       // as stored in its part
    std::string qualified;  // name used for mapping: part name + "." + name in multi-part files
                            // when the name has no '.' of its own, else the name itself
    SampleType type = SampleType::Float;
    int x_sampling = 1, y_sampling = 1;
    std::vector<unsigned char> bytes;  // raw samples over the part's data window, rows top-down
};

struct ExrPart {
    Imf::Header header;  // kept as read: compression, windows, tiling, every attribute
    int width = 0, height = 0;  // data window size
    std::vector<ExrChannel> channels;
};

struct ExrImage {
    std::string path;
    std::vector<ExrPart> parts;
};

// Reads scanline or tiled, single- or multi-part files. Deep parts are refused.
// Throws Error(Input) naming the file ("in.exr: not an OpenEXR file", "...: deep parts unsupported").
ExrImage readExr(const std::string& path);

// Writes all parts with their original headers to `path` through a temporary file in the same
// folder, renamed into place only when complete. Throws Error(Output) naming the file.
void writeExrAtomic(const ExrImage& image, const std::string& path);

// The two halves of writeExrAtomic, for several outputs that should appear together: writes the
// temporary beside `path` and returns its name (Error(Output) on failure, nothing left behind);
// commitExrTemporary renames it into place, discardExrTemporary removes it.
std::string writeExrTemporary(const ExrImage& image, const std::string& path);
void commitExrTemporary(const std::string& temporary, const std::string& path);
void discardExrTemporary(const std::string& temporary) noexcept;

}  // namespace decalcomp
