#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <utility>

#include "decalcomp/error.hpp"
#include "decalcomp/exr_file.hpp"
#include "decalcomp/scene.hpp"
#include "images/image_codecs.hpp"

namespace decalcomp::test {

ScopedEnv::ScopedEnv(std::string name, const char* value) : name_(std::move(name)) {
    if (const char* old = std::getenv(name_.c_str())) old_ = old;
    value ? setenv(name_.c_str(), value, 1) : unsetenv(name_.c_str());
}

ScopedEnv::~ScopedEnv() { old_ ? setenv(name_.c_str(), old_->c_str(), 1) : unsetenv(name_.c_str()); }

std::string dataPath(const std::string& relative) { return std::string(DECALCOMP_DATA_DIR) + "/" + relative; }

ScratchDir::ScratchDir() {
    static std::atomic<int> counter{0};
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("decalcomp-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
             std::to_string(rd() % 100000));
    std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

std::string shellQuote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

CommandResult runCommand(const std::string& command_line) {
    CommandResult result;
    FILE* pipe = ::popen((command_line + " 2>&1").c_str(), "r");
    if (!pipe) throw std::runtime_error("popen failed: " + command_line);
    std::array<char, 4096> buffer{};
    size_t n;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    int status = ::pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

CommandResult runCli(const std::string& arguments) {
    return runCommand(shellQuote(DECALCOMP_CLI) + " " + arguments);
}

CommandResult runGenerator(const std::string& arguments, const std::string& output, const std::string& camera) {
    return runCommand(shellQuote(DECALCOMP_GEN) + " " + arguments + " -o " + shellQuote(output) +
                      (camera.empty() ? "" : " --camera " + shellQuote(camera)));
}

std::string errorMessage(ErrorKind kind, const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "expected an error";
    return "";
}

void expectSceneError(const std::string& scene_path, const std::string& expected) {
    try {
        loadScene(scene_path);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_EQ(e.kind(), ErrorKind::Input);
        EXPECT_EQ(msg.rfind(scene_path + ": ", 0), 0u) << msg;
        EXPECT_NE(msg.find(expected), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

ExrImage imageWithChannels(const std::vector<std::string>& names) {
    ExrImage image;
    image.path = "in.exr";
    ExrPart part;
    for (const std::string& name : names) {
        ExrChannel channel;
        channel.name = channel.qualified = name;
        part.channels.push_back(channel);
    }
    image.parts.push_back(part);
    return image;
}

const ExrChannel& channel(const ExrImage& image, const std::string& qualified) {
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels)
            if (c.qualified == qualified) return c;
    throw std::runtime_error(image.path + ": no channel " + qualified);
}

std::set<std::string> qualifiedNames(const ExrImage& image) {
    std::set<std::string> names;
    for (const ExrPart& part : image.parts)
        for (const ExrChannel& c : part.channels) names.insert(c.qualified);
    return names;
}

std::size_t occurrences(const std::string& text, const std::string& needle) {
    std::size_t n = 0;
    for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
    return n;
}

Png readPng(const std::string& path) {
    std::string failure;
    const auto in = images::imageCodecs(ErrorKind::Input, path).open(path, /*straight_alpha=*/false, failure);
    EXPECT_TRUE(in) << path << ": " << failure;
    Png png;
    if (!in) return png;
    const int channels = in->header().channels;
    png.width = in->header().width;
    png.height = in->header().height;
    std::vector<std::uint8_t> stored(std::size_t(png.width) * png.height * std::size_t(channels));
    EXPECT_EQ(in->read(images::Sample::UInt8, stored.data()), "") << path;
    EXPECT_GE(channels, 3) << path;
    png.rgb.resize(std::size_t(png.width) * png.height * 3);
    for (std::size_t p = 0; p < std::size_t(png.width) * png.height && channels >= 3; ++p)
        for (std::size_t c = 0; c < 3; ++c) png.rgb[p * 3 + c] = stored[p * std::size_t(channels) + c];
    return png;
}

}  // namespace decalcomp::test
