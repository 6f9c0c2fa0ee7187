// Decodes decal textures to linear, premultiplied RGBA float (the layout Texture2D promises).
#include <OpenEXR/ImfVersion.h>
#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "decalcomp/error.hpp"
#include "decalcomp/input_file.hpp"
#include "decalcomp/memory_limit.hpp"
#include "decalcomp/textures.hpp"
#include "images/image_codecs.hpp"
#include "io/exr_plausibility.hpp"
#include "textures/colour_config.hpp"
#include "textures/quiet_stderr.hpp"

namespace decalcomp {
namespace {

// Largest texture accepted: keeps width*height*4 floats far from size_t overflow and from
// allocations no GPU could hold anyway (2^28 texels = 4 GiB of float RGBA).
constexpr std::int64_t kMaxTexels = std::int64_t(1) << 28;
// No image codec stores a texel's first channel in less than 1/4096 of its bytes (deflate tops
// out near 1032:1), so a header claiming more is corrupt or hostile.
constexpr std::uint64_t kMaxExpansion = 4096;

// Which file channels feed R, G, B and A. alpha = -1 means opaque.
struct ChannelLayout {
    std::array<int, 3> colour{0, 0, 0};
    int alpha = -1;
};

ChannelLayout channelLayout(const images::ImageHeader& spec) {
    ChannelLayout layout;
    const int n = spec.channels;
    if (n == 1) return layout;  // grey, opaque
    if (n == 2) {               // grey + alpha
        layout.alpha = 1;
        return layout;
    }
    // RGB(A...): trust the file's alpha channel, else the 4th channel, else opaque.
    layout.alpha = (spec.alpha_channel >= 0 && spec.alpha_channel < n) ? spec.alpha_channel : (n >= 4 ? 3 : -1);
    int next = 0;
    for (int c = 0; c < n && next < 3; ++c)
        if (c != layout.alpha) layout.colour[next++] = c;
    return layout;
}

// Whether the stored colour still has to be multiplied by alpha.
bool needsPremultiply(const images::ImageReader& in, AlphaMode mode) {
    switch (mode) {
        case AlphaMode::Straight:
            return true;
        case AlphaMode::Premultiplied:
            return false;
        case AlphaMode::Auto:
            break;
    }
    // 8/16-bit formats (PNG, TGA...) carry straight alpha by convention; OpenEXR is premultiplied
    // unless the file says otherwise (the Blender samples write decal:alpha = "straight").
    if (in.header().integer) return true;
    return in.stringAttribute("decal:alpha") == "straight";
}

// Per-value decoders: integer colour is sRGB-encoded, float colour is already linear.
template <typename T>
std::vector<float> srgbTable() {
    const int count = int(std::numeric_limits<T>::max()) + 1;
    std::vector<float> table(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) table[size_t(i)] = srgbToLinear(float(i) / float(count - 1));
    return table;
}

template <typename T>
std::vector<T> readPixels(images::ImageReader& in, images::Sample as, const std::string& path) {
    const images::ImageHeader& spec = in.header();
    std::vector<T> pixels(size_t(spec.width) * size_t(spec.height) * size_t(spec.channels));
    if (const std::string failure = in.read(as, pixels.data()); !failure.empty())
        throw inputError(fmt::format("cannot read '{}': {}", path, failure));
    return pixels;
}

// Fills texels from raw channel values; colour(v) and alpha(v) turn one stored value into linear.
template <typename T, typename ColourFn, typename AlphaFn>
void decodeTexels(const std::vector<T>& raw, int channels, const ChannelLayout& layout, bool premultiply,
                  ColourFn colour, AlphaFn alpha, std::vector<glm::vec4>& texels) {
    for (size_t i = 0; i < texels.size(); ++i) {
        const T* px = raw.data() + i * size_t(channels);
        const float a = layout.alpha >= 0 ? alpha(px[layout.alpha]) : 1.0f;
        glm::vec4 t(colour(px[layout.colour[0]]), colour(px[layout.colour[1]]), colour(px[layout.colour[2]]), a);
        if (premultiply) {
            t.r *= a;
            t.g *= a;
            t.b *= a;
        }
        texels[i] = t;
    }
}

// Reads stored integers natively so the sRGB decode is a table lookup of the exact curve.
// Data textures (normal maps, ORM) skip the sRGB curve: stored values are the data, normalised.
template <typename T>
void decodeIntegerNative(images::ImageReader& in, images::Sample as, const ChannelLayout& layout, bool premultiply,
                         TextureContent content, Texture2D& tex) {
    const std::vector<T> raw = readPixels<T>(in, as, tex.source);
    const float maxValue = float(std::numeric_limits<T>::max());
    std::vector<float> table = srgbTable<T>();
    if (content == TextureContent::Data)
        for (std::size_t v = 0; v < table.size(); ++v) table[v] = float(v) / maxValue;
    decodeTexels(
        raw, in.header().channels, layout, premultiply, [&](T v) { return table[v]; },
        [&](T v) { return float(v) / maxValue; }, tex.texels);
}

void checkSpec(const images::ImageHeader& spec, const std::string& path) {
    if (spec.deep) throw inputError(fmt::format("'{}': deep images are not supported as textures", path));
    if (spec.depth > 1) throw inputError(fmt::format("'{}': 3D images are not supported as 2D textures", path));
    if (spec.width <= 0 || spec.height <= 0 || spec.channels <= 0)
        throw inputError(
            fmt::format("'{}': empty image ({}x{}, {} channels)", path, spec.width, spec.height, spec.channels));
    if (std::int64_t(spec.width) * std::int64_t(spec.height) > kMaxTexels)
        throw inputError(fmt::format("'{}': image too large for a texture ({}x{})", path, spec.width, spec.height));
    const std::uint64_t texels = std::uint64_t(spec.width) * std::uint64_t(spec.height);
    // The file's samples as read, plus the float RGBA texels they become.
    const std::uint64_t sample_bytes = std::uint64_t(spec.bytes_per_sample);
    const std::uint64_t decoded = texels * (std::uint64_t(spec.channels) * sample_bytes + sizeof(glm::vec4));
    std::error_code ec;
    const std::uint64_t stored = std::filesystem::file_size(path, ec);
    if (!ec && texels * sample_bytes > stored * kMaxExpansion)
        throw inputError(fmt::format("'{}': header claims {}x{} texels, which {} of file cannot hold; the file is "
                                     "corrupt or truncated",
                                     path, spec.width, spec.height, readableBytes(stored)));
    requireWithinMemoryLimit(decoded, path, fmt::format("{}x{} texture", spec.width, spec.height));
}

// OpenImageIO's EXR reader allocates the chunk tables a header claims while it opens the file,
// before checkSpec can look at the size: EXR textures get the frames' checks first (found by
// fuzzing: a header claiming a huge window took gigabytes inside open()).
void requirePlausibleExrTexture(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    if (in.read(magic, sizeof magic) && Imf::isImfMagic(magic)) io::requirePlausibleExr(path);
}

// A colour-managed texture: stored values as they are (normalised integers, floats), straight
// alpha, so OpenColorIO sees the encoded colour it expects; premultiplied after conversion.
void decodeManaged(images::ImageReader& in, const ChannelLayout& layout, bool file_is_straight,
                   const TextureColour& colour, Texture2D& tex) {
    // Which space the stored values are in is known from the header: fail before reading pixels.
    const bool integer = in.header().integer;
    const std::string& from = integer ? colour.integer_space : colour.float_space;
    if (from.empty())
        throw inputError(fmt::format("'{}': no colour space known for {} texture ({} names none of the usual ones): "
                                     "give its 'colorspace', or the scene's texture_colorspaces.{}",
                                     tex.source, integer ? "an integer" : "a float", colour.config->file(),
                                     integer ? "integer" : "float"));
    const std::vector<float> raw = readPixels<float>(in, images::Sample::Float, tex.source);
    decodeTexels(
        raw, in.header().channels, layout, false, [](float v) { return v; }, [](float v) { return v; }, tex.texels);
    if (!file_is_straight)  // a premultiplied float file: the colour itself, before converting
        for (glm::vec4& t : tex.texels)
            if (t.a > 0.0f) t = glm::vec4(glm::vec3(t) / t.a, t.a);
    colour.config->convert(tex.texels, from, colour.working_space);
    for (glm::vec4& t : tex.texels) t = glm::vec4(glm::vec3(t) * t.a, t.a);
}

Texture2D decodeTexture(const std::string& path, AlphaMode alpha, TextureContent content,
                        const TextureColour* colour) {
    requirePlausibleExrTexture(path);

    const images::Codecs& codecs = images::imageCodecs(ErrorKind::Input, fmt::format("texture '{}'", path));
    std::string failure;
    const std::unique_ptr<images::ImageReader> in = codecs.open(path, /*straight_alpha=*/true, failure);
    if (!in) throw inputError(fmt::format("cannot open '{}': {}", path, failure));

    const images::ImageHeader& spec = in->header();
    checkSpec(spec, path);
    const ChannelLayout layout = channelLayout(spec);
    const bool premultiply = needsPremultiply(*in, alpha);

    Texture2D tex;
    tex.source = path;
    tex.width = spec.width;
    tex.height = spec.height;
    tex.texels.resize(size_t(spec.width) * size_t(spec.height));

    if (colour && content == TextureContent::Colour) {
        decodeManaged(*in, layout, premultiply, *colour, tex);
    } else if (spec.stored == images::Sample::UInt8) {
        decodeIntegerNative<std::uint8_t>(*in, images::Sample::UInt8, layout, premultiply, content, tex);
    } else if (spec.stored == images::Sample::UInt16) {
        decodeIntegerNative<std::uint16_t>(*in, images::Sample::UInt16, layout, premultiply, content, tex);
    } else {
        // Other integer types arrive normalised to [0,1] and are still sRGB; float stays linear.
        const bool srgb = spec.integer && content == TextureContent::Colour;
        const std::vector<float> raw = readPixels<float>(*in, images::Sample::Float, path);
        decodeTexels(
            raw, spec.channels, layout, premultiply, [&](float v) { return srgb ? srgbToLinear(v) : v; },
            [](float v) { return v; }, tex.texels);
    }
    return tex;
}

}  // namespace

Texture2D loadTexture2D(const std::string& path, AlphaMode alpha, TextureContent content,
                        const TextureColour* colour) {
    requireInputFile(path, "texture");
    const QuietStderr quiet;  // libpng's own lines; its failures come back through OpenImageIO's error
    return decodeTexture(path, alpha, content, colour);
}

}  // namespace decalcomp
