// The module decalcomp-images.so: image_codecs.hpp's interface over OpenImageIO (and, through its
// ColorConfig, OpenColorIO). It links nothing of decalcomp's, so it loads into any program.
#include <OpenImageIO/color.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "images/image_codecs.hpp"

namespace decalcomp::images {
namespace {

// Library messages may span lines; decalcomp's errors are one line.
std::string oneLine(std::string message) {
    while (!message.empty() && (message.back() == '\n' || message.back() == '\r')) message.pop_back();
    for (char& c : message)
        if (c == '\n' || c == '\r') c = ' ';
    return message.empty() ? "unknown error" : message;
}

OIIO::TypeDesc typeOf(Sample sample) {
    switch (sample) {
        case Sample::UInt8:
            return OIIO::TypeDesc::UINT8;
        case Sample::UInt16:
            return OIIO::TypeDesc::UINT16;
        case Sample::Float:
            break;
    }
    return OIIO::TypeDesc::FLOAT;
}

class OiioReader final : public ImageReader {
public:
    explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)), spec_(in_->spec()) {
        header_.format = in_->format_name();
        header_.width = spec_.width;
        header_.height = spec_.height;
        header_.depth = spec_.depth;
        header_.channels = spec_.nchannels;
        header_.deep = spec_.deep;
        header_.integer = !spec_.format.is_floating_point();
        header_.stored = spec_.format == OIIO::TypeDesc::UINT8    ? Sample::UInt8
                         : spec_.format == OIIO::TypeDesc::UINT16 ? Sample::UInt16
                                                                  : Sample::Float;
        header_.bytes_per_sample = int(spec_.format.size());
        header_.alpha_channel = spec_.alpha_channel;
        header_.channel_names = spec_.channelnames;
    }
    ~OiioReader() override { in_->close(); }

    const ImageHeader& header() const override { return header_; }
    std::string stringAttribute(const std::string& name) const override { return spec_.get_string_attribute(name); }
    std::string read(Sample as, void* pixels) override {
        if (in_->read_image(0, 0, 0, spec_.nchannels, typeOf(as), pixels)) return "";
        return oneLine(in_->geterror());
    }

private:
    std::unique_ptr<OIIO::ImageInput> in_;
    OIIO::ImageSpec spec_;
    ImageHeader header_;
};

class OiioColourConfig final : public ColourConfigFile {
public:
    explicit OiioColourConfig(const std::string& file) : config_(file) {}
    OIIO::ColorConfig& config() { return config_; }

    std::vector<std::string> spaceNames() const override { return config_.getColorSpaceNames(); }
    std::string convert(float* rgba, std::size_t count, const std::string& from, const std::string& to) const override {
        const OIIO::ColorProcessorHandle processor = config_.createColorProcessor(from, to);
        if (!processor) return oneLine(config_.geterror());
        if (processor->isNoOp()) return "";
        // One row of RGBA texels: OpenColorIO converts the first three channels and keeps alpha.
        constexpr OIIO::stride_t kTexel = 4 * sizeof(float);
        processor->apply(rgba, int(count), 1, 4, sizeof(float), kTexel, OIIO::stride_t(kTexel * count));
        return "";
    }

private:
    mutable OIIO::ColorConfig config_;
};

class OiioCodecs final : public Codecs {
public:
    std::unique_ptr<ImageReader> open(const std::string& path, bool straight_alpha, std::string& error) const override {
        // Without the hint OIIO premultiplies 8-bit straight-alpha PNG/TGA on read.
        OIIO::ImageSpec config;
        if (straight_alpha) config.attribute("oiio:UnassociatedAlpha", 1);
        auto in = OIIO::ImageInput::open(path, &config);
        if (!in) {
            error = oneLine(OIIO::geterror());
            return nullptr;
        }
        return std::make_unique<OiioReader>(std::move(in));
    }

    std::string write(const std::string& path, const ImageToWrite& image) const override {
        OIIO::ImageSpec spec(image.width, image.height, image.channels, typeOf(image.sample));
        if (!image.channel_names.empty()) spec.channelnames = image.channel_names;
        if (image.alpha_channel >= 0) spec.alpha_channel = image.alpha_channel;
        if (image.straight_alpha) spec.attribute("oiio:UnassociatedAlpha", 1);
        for (const auto& [name, value] : image.attributes) spec.attribute(name, value);
        auto out = OIIO::ImageOutput::create(image.format);
        if (out && out->open(path, spec) && out->write_image(typeOf(image.sample), image.pixels) && out->close())
            return "";
        return oneLine(out ? out->geterror() : OIIO::geterror());
    }

    std::vector<float> resize(const std::vector<float>& pixels, int width, int height, int channels, int new_width,
                              int new_height) const override {
        OIIO::ImageBuf full(OIIO::ImageSpec(width, height, channels, OIIO::TypeDesc::FLOAT));
        full.set_pixels(OIIO::ROI(0, width, 0, height, 0, 1, 0, channels), OIIO::TypeDesc::FLOAT, pixels.data());
        const OIIO::ROI small_roi(0, new_width, 0, new_height, 0, 1, 0, channels);
        const OIIO::ImageBuf small = OIIO::ImageBufAlgo::resize(full, "", 0.0f, small_roi);
        std::vector<float> out(std::size_t(new_width) * std::size_t(new_height) * std::size_t(channels));
        small.get_pixels(small_roi, OIIO::TypeDesc::FLOAT, out.data());
        return out;
    }

    std::unique_ptr<ColourConfigFile> openColourConfig(const std::string& path, std::string& error) const override {
        auto file = std::make_unique<OiioColourConfig>(path);
        if (file->config().has_error()) {
            error = oneLine(file->config().geterror());
            return nullptr;
        }
        if (file->config().getNumColorSpaces() <= 0) {
            error = "it defines no colour spaces";
            return nullptr;
        }
        return file;
    }
};

}  // namespace
}  // namespace decalcomp::images

extern "C" {
__attribute__((visibility("default"))) int decalcomp_image_codecs_version() {
    return decalcomp::images::kCodecsVersion;
}
__attribute__((visibility("default"))) const decalcomp::images::Codecs* decalcomp_image_codecs() {
    static const decalcomp::images::OiioCodecs codecs;
    return &codecs;
}
}
