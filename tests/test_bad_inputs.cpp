// The bad-input matrix of issue 10 ("Nothing lost, nothing crashes"): one table of hostile or
// mistaken runs, each its own test (BadInputs/Matrix.<name>). Every case runs the CLI on copies in
// a scratch folder and asserts:
// - the documented exit code (docs/cli.md: 0, 2 usage, 3 input, 4 OpenCL, 5 output; never 1 or a
//   signal);
// - one message format: every line the run prints (all runs are -q) starts with
//   "decalcomp: error: " or "decalcomp: warning: ", never "internal error", never a raw libpng
//   line or a 300-digit number; an error case has an error line, a warning case a warning line,
//   that names the file or field (the case's needles);
// - nothing is left in the output folder (only the expected outputs for runs that succeed, or for
//   a batch the frames before the one that failed), no temporaries anywhere;
// - every input is unchanged: each file under the scratch folder (outside the output folder) is
//   checksummed (FNV-1a) before and after, symbolic links by where they point, and nothing appears
//   or disappears there;
// - hostile sizes fail at once: those runs get 4 GiB of address space and 5 CPU seconds.
// Inputs are 64x48 G-buffers from decalcomp-gbuffer-gen, a three-frame sequence, and copies of
// the sample textures; hostile ones are made here by patching header bytes, truncating, flipping
// bytes or rewriting channels.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTileDescription.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "decalcomp/camera.hpp"
#include "decalcomp/exr_file.hpp"
#include "support/batch_fixture.hpp"
#include "support/test_support.hpp"

namespace decalcomp {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;

// ---------------------------------------------------------------------------------------------
// Files: bytes, checksums, snapshots

void writeBytes(const fs::path& path, const std::string& bytes) {
    fs::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

void writeText(const fs::path& path, const std::string& text) { writeBytes(path, text); }

std::uint64_t fnv1a(const std::string& bytes) {
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
    return h;
}

// Every entry under `root` except the folder `skip`: "file <size> <fnv1a>", "link -> <target>",
// "dir".
using Snapshot = std::map<std::string, std::string>;

Snapshot snapshot(const fs::path& root, const fs::path& skip) {
    Snapshot s;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(root, ec); it != fs::recursive_directory_iterator();
         it.increment(ec)) {
        if (ec) break;
        const fs::path p = it->path();
        if (p == skip) {
            it.disable_recursion_pending();
            continue;
        }
        const std::string rel = fs::relative(p, root).string();
        const fs::file_status st = fs::symlink_status(p);
        if (fs::is_symlink(st)) {
            s[rel] = "link -> " + fs::read_symlink(p).string();
        } else if (fs::is_directory(st)) {
            s[rel] = "dir";
        } else {
            const std::string bytes = test::readFileBytes(p);
            s[rel] = "file " + std::to_string(bytes.size()) + " " + std::to_string(fnv1a(bytes));
        }
    }
    return s;
}

// What differs between two snapshots, one line per entry ("" when none).
std::string snapshotDifference(const Snapshot& before, const Snapshot& after) {
    std::string out;
    for (const auto& [path, what] : before) {
        auto it = after.find(path);
        if (it == after.end())
            out += "  removed: " + path + "\n";
        else if (it->second != what)
            out += "  changed: " + path + " (" + what + " -> " + it->second + ")\n";
    }
    for (const auto& [path, what] : after)
        if (!before.count(path)) out += "  appeared: " + path + " (" + what + ")\n";
    return out;
}

// Every entry under `dir` (hidden ones too), relative, sorted.
std::set<std::string> listTree(const fs::path& dir) {
    std::set<std::string> names;
    std::error_code ec;
    if (!fs::exists(dir, ec)) return names;
    for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator();
         it.increment(ec)) {
        if (ec) break;
        names.insert(fs::relative(it->path(), dir).string());
    }
    return names;
}

std::string joined(const std::set<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "(nothing)" : out;
}

// ---------------------------------------------------------------------------------------------
// EXR bytes: header attributes, patched in place

void putI32(std::string& bytes, std::size_t at, std::int32_t v) { std::memcpy(&bytes[at], &v, 4); }
void putU64(std::string& bytes, std::size_t at, std::uint64_t v) { std::memcpy(&bytes[at], &v, 8); }

struct HeaderAttribute {
    std::string name, type;
    std::size_t value_at = 0, size = 0;
};

// The first header's attributes, and where that header ends (just past its terminating zero).
std::vector<HeaderAttribute> headerAttributes(const std::string& bytes, std::size_t* header_end = nullptr) {
    std::vector<HeaderAttribute> attributes;
    std::size_t at = 8;  // magic and version
    auto readString = [&](std::string& s) {
        const std::size_t zero = bytes.find('\0', at);
        if (zero == std::string::npos) throw std::runtime_error("EXR header: unterminated string");
        s = bytes.substr(at, zero - at);
        at = zero + 1;
    };
    while (at < bytes.size()) {
        HeaderAttribute a;
        readString(a.name);
        if (a.name.empty()) break;
        readString(a.type);
        std::int32_t size = 0;
        std::memcpy(&size, &bytes[at], 4);
        at += 4;
        a.value_at = at;
        a.size = std::size_t(size);
        at += a.size;
        attributes.push_back(a);
    }
    if (header_end) *header_end = at;
    return attributes;
}

// By value: callers look attributes up in a temporary list.
HeaderAttribute attribute(const std::vector<HeaderAttribute>& attributes, const std::string& name) {
    for (const HeaderAttribute& a : attributes)
        if (a.name == name) return a;
    throw std::runtime_error("EXR header: no attribute " + name);
}

// Sets a box2i attribute (dataWindow, displayWindow) of the file's first header.
void patchBox(const fs::path& path, const std::string& name, std::int32_t x0, std::int32_t y0, std::int32_t x1,
              std::int32_t y1) {
    std::string bytes = test::readFileBytes(path);
    const HeaderAttribute& a = attribute(headerAttributes(bytes), name);
    if (a.type != "box2i" || a.size != 16) throw std::runtime_error(name + " is not a box2i");
    putI32(bytes, a.value_at, x0);
    putI32(bytes, a.value_at + 4, y0);
    putI32(bytes, a.value_at + 8, x1);
    putI32(bytes, a.value_at + 12, y1);
    writeBytes(path, bytes);
}

// Replaces `path` with an input a fuzz target once failed on (tests/fuzz/regressions/<relative>).
void replaceWithFuzzFinding(const fs::path& path, const std::string& relative) {
    const fs::path finding = fs::path(DECALCOMP_DATA_DIR).parent_path() / "tests/fuzz/regressions" / relative;
    fs::copy_file(finding, path, fs::copy_options::overwrite_existing);
}

void truncateTo(const fs::path& path, std::size_t size) {
    std::string bytes = test::readFileBytes(path);
    bytes.resize(std::min(size, bytes.size()));
    writeBytes(path, bytes);
}

void flipBytes(const fs::path& path, std::size_t at, std::size_t count) {
    std::string bytes = test::readFileBytes(path);
    for (std::size_t i = at; i < at + count && i < bytes.size(); ++i) bytes[i] = char(~bytes[i]);
    writeBytes(path, bytes);
}

std::size_t headerEnd(const fs::path& path) {
    std::size_t end = 0;
    headerAttributes(test::readFileBytes(path), &end);
    return end;
}

// A scanline, uncompressed EXR header with `channels` FLOAT channels over a width x height window,
// and its offset table, but no pixel data at all (hostile channel counts).
std::string headerOnlyExr(int channels, int width, int height) {
    std::string out("\x76\x2f\x31\x01", 4);
    const std::int32_t version = 2;
    out.append(reinterpret_cast<const char*>(&version), 4);
    auto attr = [&](const std::string& name, const std::string& type, const std::string& value) {
        out += name;
        out += '\0';
        out += type;
        out += '\0';
        const std::int32_t size = std::int32_t(value.size());
        out.append(reinterpret_cast<const char*>(&size), 4);
        out += value;
    };
    auto i32 = [](std::int32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    auto f32 = [](float v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    std::string chlist;
    for (int c = 0; c < channels; ++c) {
        char name[16];
        std::snprintf(name, sizeof name, "c%06d", c);
        chlist += name;
        chlist += '\0';
        chlist += i32(2);                // FLOAT
        chlist += std::string(4, '\0');  // pLinear, reserved
        chlist += i32(1) + i32(1);       // sampling
    }
    chlist += '\0';
    attr("channels", "chlist", chlist);
    attr("compression", "compression", std::string(1, '\0'));
    const std::string box = i32(0) + i32(0) + i32(width - 1) + i32(height - 1);
    attr("dataWindow", "box2i", box);
    attr("displayWindow", "box2i", box);
    attr("lineOrder", "lineOrder", std::string(1, '\0'));
    attr("pixelAspectRatio", "float", f32(1.0f));
    attr("screenWindowCenter", "v2f", f32(0.0f) + f32(0.0f));
    attr("screenWindowWidth", "float", f32(1.0f));
    out += '\0';
    const std::uint64_t first = out.size() + 8ull * std::uint64_t(height);
    const std::uint64_t line = 8ull + 4ull * std::uint64_t(channels) * std::uint64_t(width);
    for (int y = 0; y < height; ++y) {
        const std::uint64_t offset = first + line * std::uint64_t(y);
        out.append(reinterpret_cast<const char*>(&offset), 8);
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// EXR channels, rewritten through the library's reader and writer

void editExr(const fs::path& path, const std::function<void(ExrImage&)>& edit) {
    ExrImage image = readExr(path.string());
    edit(image);
    writeExrAtomic(image, path.string());
}

ExrChannel& channelNamed(ExrPart& part, const std::string& name) {
    for (ExrChannel& c : part.channels)
        if (c.name == name) return c;
    throw std::runtime_error("no channel " + name);
}

void fillFloat(ExrChannel& channel, const std::function<float(std::size_t)>& value) {
    const std::size_t n = channel.bytes.size() / 4;
    for (std::size_t i = 0; i < n; ++i) {
        const float v = value(i);
        std::memcpy(&channel.bytes[i * 4], &v, 4);
    }
}

void removeChannels(ExrPart& part, const std::function<bool(const std::string&)>& drop) {
    Imf::ChannelList kept;
    for (auto it = part.header.channels().begin(); it != part.header.channels().end(); ++it)
        if (!drop(it.name())) kept.insert(it.name(), it.channel());
    part.header.channels() = kept;
    std::vector<ExrChannel> channels;
    for (ExrChannel& c : part.channels)
        if (!drop(c.name)) channels.push_back(std::move(c));
    part.channels = std::move(channels);
}

void addFloatChannel(ExrPart& part, const std::string& name, const std::vector<float>& values) {
    part.header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    ExrChannel c;
    c.name = c.qualified = name;
    c.type = SampleType::Float;
    c.bytes.resize(values.size() * 4);
    std::memcpy(c.bytes.data(), values.data(), c.bytes.size());
    part.channels.push_back(std::move(c));
}

// ---------------------------------------------------------------------------------------------
// Cryptomatte, built here from the generator's object ids (floor 1, wall 2, sphere 3, box 4)

std::uint32_t murmur3(std::string_view key) {
    const std::uint32_t c1 = 0xcc9e2d51, c2 = 0x1b873593;
    std::uint32_t h = 0;
    const std::size_t blocks = key.size() / 4;
    auto rotl = [](std::uint32_t x, int r) { return (x << r) | (x >> (32 - r)); };
    for (std::size_t i = 0; i < blocks; ++i) {
        std::uint32_t k;
        std::memcpy(&k, key.data() + i * 4, 4);
        k *= c1;
        k = rotl(k, 15);
        k *= c2;
        h ^= k;
        h = rotl(h, 13);
        h = h * 5 + 0xe6546b64;
    }
    std::uint32_t k = 0;
    const unsigned char* tail = reinterpret_cast<const unsigned char*>(key.data()) + blocks * 4;
    switch (key.size() & 3) {
        case 3:
            k ^= std::uint32_t(tail[2]) << 16;
            [[fallthrough]];
        case 2:
            k ^= std::uint32_t(tail[1]) << 8;
            [[fallthrough]];
        case 1:
            k ^= tail[0];
            k *= c1;
            k = rotl(k, 15);
            k *= c2;
            h ^= k;
    }
    h ^= std::uint32_t(key.size());
    h ^= h >> 16;
    h *= 0x85ebca6b;
    h ^= h >> 13;
    h *= 0xc2b2ae35;
    h ^= h >> 16;
    return h;
}

// The specification's uint32_to_float32: exponent clamped to [1, 254].
std::uint32_t cryptoBits(std::uint32_t hash) {
    std::uint32_t exponent = (hash >> 23) & 255u;
    exponent = std::min(std::max(exponent, 1u), 254u);
    return (hash & 0x807fffffu) | (exponent << 23);
}

float bitsAsFloat(std::uint32_t bits) {
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

const std::map<std::uint32_t, std::string> kObjectNames = {{1, "Floor"}, {2, "Wall"}, {3, "Sphere"}, {4, "Box"}};

std::string cryptoManifest() {
    nlohmann::json m = nlohmann::json::object();
    for (const auto& [id, name] : kObjectNames) {
        char hex[9];
        std::snprintf(hex, sizeof hex, "%08x", cryptoBits(murmur3(name)));
        m[name] = hex;
    }
    return m.dump();
}

struct CryptoOptions {
    std::string manifest;    // inline manifest ("" = none)
    std::string manif_file;  // sidecar name ("" = none)
    std::array<std::string, 4> suffixes{"r", "g", "b", "a"};
};

// Adds a CryptoObject layer (rank 0 only: the pixel's object at full coverage) to a generic frame.
void addCryptomatte(const fs::path& exr, const CryptoOptions& o) {
    editExr(exr, [&](ExrImage& image) {
        ExrPart& part = image.parts.at(0);
        const ExrChannel& id = channelNamed(part, "id");
        const std::size_t n = id.bytes.size() / 4;
        std::vector<float> rank_id(n), coverage(n), zero(n, 0.0f);
        for (std::size_t i = 0; i < n; ++i) {
            std::uint32_t object = 0;
            std::memcpy(&object, &id.bytes[i * 4], 4);
            auto it = kObjectNames.find(object);
            rank_id[i] = it == kObjectNames.end() ? 0.0f : bitsAsFloat(cryptoBits(murmur3(it->second)));
            coverage[i] = it == kObjectNames.end() ? 0.0f : 1.0f;
        }
        addFloatChannel(part, "CryptoObject00." + o.suffixes[0], rank_id);
        addFloatChannel(part, "CryptoObject00." + o.suffixes[1], coverage);
        addFloatChannel(part, "CryptoObject00." + o.suffixes[2], zero);
        addFloatChannel(part, "CryptoObject00." + o.suffixes[3], zero);
        const std::string key = "cryptomatte/f834d0a/";
        part.header.insert(key + "name", Imf::StringAttribute("CryptoObject"));
        part.header.insert(key + "hash", Imf::StringAttribute("MurmurHash3_32"));
        part.header.insert(key + "conversion", Imf::StringAttribute("uint32_to_float32"));
        if (!o.manifest.empty()) part.header.insert(key + "manifest", Imf::StringAttribute(o.manifest));
        if (!o.manif_file.empty()) part.header.insert(key + "manif_file", Imf::StringAttribute(o.manif_file));
    });
}

// ---------------------------------------------------------------------------------------------
// PNG bytes: chunks, CRCs

std::uint32_t crc32(const std::string& bytes, std::size_t at, std::size_t count) {
    std::uint32_t crc = 0xffffffffu;
    for (std::size_t i = at; i < at + count; ++i) {
        crc ^= static_cast<unsigned char>(bytes[i]);
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

void putBE32(std::string& bytes, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes[at + i] = char((v >> (24 - 8 * i)) & 0xff);
}

std::uint32_t getBE32(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
}

// Where chunk `type` starts (its length field), else npos.
std::size_t pngChunk(const std::string& bytes, const std::string& type) {
    std::size_t at = 8;
    while (at + 8 <= bytes.size()) {
        if (bytes.compare(at + 4, 4, type) == 0) return at;
        at += 12 + getBE32(bytes, at);
    }
    return std::string::npos;
}

// Sets the PNG's IHDR width and height, CRC recomputed: a valid header of a huge image.
void patchPngSize(const fs::path& path, std::uint32_t width, std::uint32_t height) {
    std::string bytes = test::readFileBytes(path);
    const std::size_t ihdr = pngChunk(bytes, "IHDR");
    putBE32(bytes, ihdr + 8, width);
    putBE32(bytes, ihdr + 12, height);
    putBE32(bytes, ihdr + 8 + 13, crc32(bytes, ihdr + 4, 4 + 13));
    writeBytes(path, bytes);
}

// Inserts an ancillary tEXt chunk with a wrong CRC after IHDR: libpng warns and goes on.
void insertBadTextChunk(const fs::path& path) {
    std::string bytes = test::readFileBytes(path);
    const std::size_t after_ihdr = pngChunk(bytes, "IHDR") + 12 + 13;
    const std::string data = std::string("Comment") + '\0' + "bad crc";
    std::string chunk(4, '\0');
    putBE32(chunk, 0, std::uint32_t(data.size()));
    chunk += "tEXt" + data + std::string(4, '\0');
    putBE32(chunk, chunk.size() - 4, crc32(chunk, 4, 4 + data.size()) ^ 0x5a5a5a5au);
    bytes.insert(after_ihdr, chunk);
    writeBytes(path, bytes);
}

// Flips bytes inside the first IDAT's data, CRC left as it was: libpng's CRC error.
void corruptPngData(const fs::path& path) {
    std::string bytes = test::readFileBytes(path);
    const std::size_t idat = pngChunk(bytes, "IDAT");
    for (std::size_t i = idat + 8 + 16; i < idat + 8 + 48; ++i) bytes[i] = char(~bytes[i]);
    writeBytes(path, bytes);
}

// ---------------------------------------------------------------------------------------------
// The inputs every case starts from (built once per process, copied into each case's folder)

constexpr int kWidth = 64, kHeight = 48;

const char* const kScorch =
    R"({"name": "floor_scorch", "texture": "scorch", "translate": [0.3, -1.6, 0.0], "rotate_deg": [0, 0, 20], "scale": [1.6, 1.6, 0.5])";
const char* const kStripes =
    R"({"name": "wall_stripes", "texture": "stripes", "translate": [0.5, 3.0, 1.8], "rotate_deg": [90, 0, 0], "scale": [2.0, 1.0, 0.5]})";
const char* const kTextures = R"("textures": {"scorch": "textures/scorch.png", "stripes": "textures/stripes.png"})";

// A scene with the base textures and these decals (a JSON array's contents).
std::string sceneWith(const std::string& decals, const std::string& textures = kTextures) {
    return "{" + textures + ",\n \"decals\": [" + decals + "]}\n";
}

const char* const kProfile = R"({"name": "studio", "attributes": {"depth": ["Z"], "albedo": ["albedo.{R,G,B}"],
  "position": ["P.{X,Y,Z}"], "normal": ["N.{X,Y,Z}"], "object_id": ["id"]}})";

void expectOk(const CommandResult& r, const std::string& what) {
    if (r.exit_code != 0) throw std::runtime_error(what + " failed: " + r.output);
}

fs::path baseInputs() {
    static test::ScratchDir dir;
    static bool built = false;
    if (built) return dir.path();
    const fs::path in = dir.path();
    expectOk(test::runGenerator(fmt::format("--naming generic --width {} --height {}", kWidth, kHeight),
                                (in / "frame.exr").string(), (in / "camera.json").string()),
             "generator (frame.exr)");
    expectOk(test::runGenerator(fmt::format("--per-pass --width {} --height {}", kWidth, kHeight),
                                (in / "pp.exr").string(), (in / "pp.camera.json").string()),
             "generator (per-pass)");
    fs::create_directories(in / "textures");
    for (const char* t : {"scorch.png", "stripes.png", "cloud_volume.exr"})
        fs::copy_file(test::dataPath(std::string("sample/textures/") + t), in / "textures" / t);
    writeText(in / "scene.json", sceneWith(std::string(kScorch) + "},\n  " + kStripes));
    writeText(in / "profile.json", kProfile);
    // a three-frame sequence with the camera in each header, a sidecar per frame, a static scene
    const fs::path seq = in / "seq";
    test::writeSequence(seq, {1, 2, 3}, kWidth, kHeight);
    test::writeStaticScene(seq);
    for (int f : {1, 2, 3})
        saveCameraJson(test::sequenceCamera(f, kWidth, kHeight), kWidth, kHeight,
                       (seq / fmt::format("cam.{:04d}.json", f)).string());
    built = true;
    return dir.path();
}

// One case's folder: in/ (a copy of the base inputs), out/ (the output folder, empty).
struct Env {
    fs::path root;
    fs::path in() const { return root / "in"; }
    fs::path out() const { return root / "out"; }
    fs::path at(const std::string& relative) const { return in() / relative; }
};

// The camera sidecar, edited as JSON.
void editJson(const fs::path& path, const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = nlohmann::json::parse(test::readFileBytes(path));
    edit(j);
    writeText(path, j.dump(2));
}

nlohmann::json matrixJson(const glm::dmat4& m) {  // row-major rows of a column-major glm matrix
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
    return rows;
}

void setProjection(const Env& e, const glm::dmat4& projection, const std::string& camera = "camera.json") {
    editJson(e.at(camera), [&](nlohmann::json& j) { j["projection"] = matrixJson(projection); });
}

// An OpenGL perspective projection (column-major, p[col][row]), written out here so a far plane
// before the near one is exactly what the file says.
glm::dmat4 glPerspective(double fov_y_deg, double aspect, double near_plane, double far_plane) {
    const double f = 1.0 / std::tan(fov_y_deg * 3.14159265358979323846 / 360.0);
    glm::dmat4 p(0.0);
    p[0][0] = f / aspect;
    p[1][1] = f;
    p[2][2] = -(far_plane + near_plane) / (far_plane - near_plane);
    p[2][3] = -1.0;
    p[3][2] = -2.0 * far_plane * near_plane / (far_plane - near_plane);
    return p;
}

glm::dmat4 demoProjection(double near_plane, double far_plane) {
    return glPerspective(50.0, double(kWidth) / kHeight, near_plane, far_plane);
}

// The composited albedo differs from the input's somewhere (the run did something).
void expectAlbedoChanged(const Env& e, const std::string& input, const std::string& output,
                         const std::string& channel = "albedo.R") {
    ASSERT_TRUE(fs::exists(e.out() / output)) << output;
    const ExrImage a = readExr(e.at(input).string()), b = readExr((e.out() / output).string());
    EXPECT_NE(test::channel(a, channel).bytes, test::channel(b, channel).bytes)
        << output << ": the run changed no albedo sample";
}

// ---------------------------------------------------------------------------------------------
// The matrix

enum class Expect {
    Error,    // the exit code, no output; an error line with every needle
    Warning,  // exit 0, the outputs; a warning line with every needle
    Works,    // exit 0, the outputs; warnings allowed but none needed (needles: none)
    Clean,    // exit 0, the outputs, and nothing printed at all (the run is -q)
};

struct Case {
    std::string name;
    std::string args;  // {in}, {out} and {root} stand for the case's folders
    int exit_code = 0;
    Expect expect = Expect::Error;
    std::vector<std::string> needles;                 // each in the message line; "a||b" takes either
    std::function<void(const Env&)> setup = nullptr;  // writes or damages inputs before the run
    std::set<std::string> outputs = {};               // what out/ holds afterwards
    bool memory_cap = false;  // hostile sizes: under `ulimit -v` (4 GiB) and `ulimit -t` (5 CPU seconds)
    std::function<void(const Env&)> verify = nullptr;  // further checks after the run
};

// The base commands: a composite of the generic frame, and of the per-pass files.
std::string composite(const std::string& scene = "{in}/scene.json", const std::string& camera = "{in}/camera.json",
                      const std::string& input = "{in}/frame.exr") {
    return "composite " + input + " --decals " + scene + " --camera " + camera + " --device cpu -q";
}
std::string perPass(const std::string& scene = "{in}/scene.json", const std::string& depth = "{in}/pp.depth.exr") {
    return "composite {in}/pp.exr --pass depth=" + depth + " --pass albedo={in}/pp.albedo.exr --decals " + scene +
           " --camera {in}/pp.camera.json --device cpu -q";
}
const std::string C = composite();
const std::string O = " -o {out}/r.exr";
const std::string PP = perPass();
const std::string B = "batch {in}/seq/frame.####.exr --decals {in}/seq/static_scene.json --device cpu -q --frames 1-3";
const std::string BO = " -o {out}/c.####.exr";

void sceneFile(const Env& e, const std::string& text) { writeText(e.at("scene.json"), text); }

std::vector<Case> cases() {
    std::vector<Case> v;
    auto add = [&](Case c) { v.push_back(std::move(c)); };
    const std::set<std::string> r_exr = {"r.exr"};

    // ---- anchors: the clean inputs work (so the damage is what the other cases test) ----
    add({"clean_composite_works", C + O, 0, Expect::Clean, {}, nullptr, r_exr, false, [](const Env& e) {
             expectAlbedoChanged(e, "frame.exr", "r.exr");
         }});
    add({"clean_per_pass_works", PP + O, 0, Expect::Clean, {}, nullptr, r_exr, false, [](const Env& e) {
             expectAlbedoChanged(e, "pp.albedo.exr", "r.exr", "R");
         }});
    add({"clean_batch_works", B + BO, 0, Expect::Clean, {}, nullptr, {"c.0001.exr", "c.0002.exr", "c.0003.exr"}});

    // ---- 1. no run overwrites what it reads ----
    add({"preview_is_the_input_exr", C + O + " --preview {in}/frame.exr", 2, Expect::Error, {"frame.exr", "preview"}});
    add({"preview_is_the_output", C + O + " --preview {out}/r.exr", 2, Expect::Error, {"r.exr", "preview"}});
    add({"output_is_the_input_exr", C + " -o {in}/frame.exr", 2, Expect::Error, {"frame.exr", "--overwrite-input"}});
    add({"output_is_a_pass_file",
         PP + " -o {in}/pp.depth.exr",
         2,
         Expect::Error,
         {"pp.depth.exr", "--overwrite-input"}});
    add({"preview_is_a_pass_file",
         PP + O + " --preview {in}/pp.depth.exr",
         2,
         Expect::Error,
         {"pp.depth.exr", "preview"}});
    add({"output_is_the_scene", C + " -o {in}/scene.json", 2, Expect::Error, {"scene.json"}});
    add({"preview_is_the_scene", C + O + " --preview {in}/scene.json", 2, Expect::Error, {"scene.json", "preview"}});
    add({"preview_is_the_camera", C + O + " --preview {in}/camera.json", 2, Expect::Error, {"camera.json", "preview"}});
    add({"preview_is_a_texture",
         C + O + " --preview {in}/textures/scorch.png",
         2,
         Expect::Error,
         {"scorch.png", "preview"}});
    add({"output_symlink_to_the_scene",
         C + " -o {in}/scene_link.exr",
         2,
         Expect::Error,
         {"scene_link.exr", "scene.json"},
         [](const Env& e) { fs::create_symlink(e.at("scene.json"), e.at("scene_link.exr")); }});
    add({"output_symlink_to_the_camera",
         C + " -o {in}/camera_link.exr --overwrite-input",
         2,
         Expect::Error,
         {"camera_link.exr", "camera.json"},
         [](const Env& e) { fs::create_symlink(e.at("camera.json"), e.at("camera_link.exr")); }});
    add({"output_symlink_to_a_texture",
         C + " -o {in}/texture_link.exr",
         2,
         Expect::Error,
         {"texture_link.exr", "scorch.png"},
         [](const Env& e) { fs::create_symlink(e.at("textures/scorch.png"), e.at("texture_link.exr")); }});
    add({"output_symlink_to_the_profile_file",
         C + " --profile-file {in}/profile.json -o {in}/profile_link.exr",
         2,
         Expect::Error,
         {"profile_link.exr", "profile.json"},
         [](const Env& e) { fs::create_symlink(e.at("profile.json"), e.at("profile_link.exr")); }});
    add({"preview_is_the_profile_file",
         C + " --profile-file {in}/profile.json" + O + " --preview {in}/profile.json",
         2,
         Expect::Error,
         {"profile.json", "preview"}});
    add({"output_symlink_to_the_input_exr",
         C + " -o {in}/frame_link.exr",
         2,
         Expect::Error,
         {"frame_link.exr", "--overwrite-input"},
         [](const Env& e) { fs::create_symlink(e.at("frame.exr"), e.at("frame_link.exr")); }});
    add({"preview_symlink_to_the_input_exr",
         C + O + " --preview {in}/frame_link.png",
         2,
         Expect::Error,
         {"frame_link.png", "preview"},
         [](const Env& e) { fs::create_symlink(e.at("frame.exr"), e.at("frame_link.png")); }});
    add({"output_hard_link_to_the_input_exr",
         C + " -o {in}/frame_alias.exr",
         2,
         Expect::Error,
         {"frame_alias.exr", "--overwrite-input"},
         [](const Env& e) { fs::create_hard_link(e.at("frame.exr"), e.at("frame_alias.exr")); }});
    add({"preview_hard_link_to_a_texture",
         C + O + " --preview {in}/texture_alias.png",
         2,
         Expect::Error,
         {"texture_alias.png", "preview"},
         [](const Env& e) { fs::create_hard_link(e.at("textures/scorch.png"), e.at("texture_alias.png")); }});
    add({"preview_dangling_symlink_to_the_output",
         C + O + " --preview {root}/links/preview.png",
         2,
         Expect::Error,
         {"preview.png", "r.exr"},
         [](const Env& e) {
             fs::create_directories(e.root / "links");
             fs::create_symlink(e.out() / "r.exr", e.root / "links" / "preview.png");
         }});
    add({"preview_is_one_of_the_folder_outputs",
         perPass("{in}/scene_normal.json") +
             " --pass normal={in}/pp.normal.exr -o {out}/ --preview {out}/pp.albedo.exr",
         2,
         Expect::Error,
         {"pp.albedo.exr", "preview"},
         [](const Env& e) {
             // a decal that changes albedo and normal: two files change, -o is a folder
             writeText(
                 e.at("scene_normal.json"),
                 sceneWith(
                     std::string(kScorch) + R"(, "affects": {"albedo": 1, "normal": {"factor": 1}}})",
                     R"("textures": {"scorch": {"albedo": "textures/scorch.png", "normal": "textures/scorch.png"}})"));
         }});
    add({"output_without_exr_extension", C + " -o {out}/r.png", 2, Expect::Error, {"r.png", ".exr"}});
    add({"output_without_any_extension", C + " -o {out}/result", 2, Expect::Error, {"result", ".exr"}});
    add({"batch_preview_pattern_is_the_input_pattern",
         B + BO + " --preview {in}/seq/frame.####.exr",
         2,
         Expect::Error,
         {"frame.", "preview"}});
    add({"batch_output_pattern_is_the_input_pattern",
         B + " -o {in}/seq/frame.####.exr",
         2,
         Expect::Error,
         {"frame.", "--overwrite-input"}});
    add({"batch_preview_pattern_is_the_output_pattern",
         B + BO + " --preview {out}/c.####.exr",
         2,
         Expect::Error,
         {"c.", "preview"}});
    add({"output_symlink_to_the_cryptomatte_manifest",
         composite("{in}/scene_crypto.json") + " -o {in}/manifest_link.exr",
         2,
         Expect::Error,
         {"manifest_link.exr", "manifest.json"},
         [](const Env& e) {
             writeText(e.at("manifest.json"), cryptoManifest());
             addCryptomatte(e.at("frame.exr"), {"", "manifest.json"});
             writeText(e.at("scene_crypto.json"),
                       sceneWith(std::string(kScorch) + R"(, "mask": {"cryptomatte": {"names": ["Floor"]}}})"));
             fs::create_symlink(e.at("manifest.json"), e.at("manifest_link.exr"));
         }});

    // ---- 2. hostile sizes fail before any allocation ----
    add({"data_window_100000_squared",
         C + O,
         3,
         Expect::Error,
         {"frame.exr", "dataWindow||data window"},
         [](const Env& e) { patchBox(e.at("frame.exr"), "dataWindow", 0, 0, 99999, 99999); },
         {},
         true});
    add({"data_window_6000_squared_in_a_small_file",
         C + O,
         3,
         Expect::Error,
         {"frame.exr", "dataWindow||data window"},
         [](const Env& e) { patchBox(e.at("frame.exr"), "dataWindow", 0, 0, 5999, 5999); },
         {},
         true});
    add({"data_window_width_overflows_int",
         C + O,
         3,
         Expect::Error,
         {"frame.exr", "dataWindow||data window"},
         [](const Env& e) {
             patchBox(e.at("frame.exr"), "dataWindow", std::numeric_limits<std::int32_t>::min() + 1, 0,
                      std::numeric_limits<std::int32_t>::max() - 1, 47);
         },
         {},
         true});
    add({"data_window_at_int_max",
         C + O,
         3,
         Expect::Error,
         {"frame.exr", "dataWindow||data window"},
         [](const Env& e) {
             patchBox(e.at("frame.exr"), "dataWindow", 0, 0, std::numeric_limits<std::int32_t>::max(),
                      std::numeric_limits<std::int32_t>::max());
         },
         {},
         true});
    add({"data_window_reversed",
         C + O,
         3,
         Expect::Error,
         {"frame.exr", "dataWindow||data window"},
         [](const Env& e) { patchBox(e.at("frame.exr"), "dataWindow", 63, 47, 0, 0); },
         {},
         true});
    add({"tiled_file_with_a_huge_data_window",
         C + O,
         3,
         Expect::Error,
         {"frame.exr", "dataWindow||data window"},
         [](const Env& e) {
             editExr(e.at("frame.exr"), [](ExrImage& image) {
                 image.parts.at(0).header.setTileDescription(Imf::TileDescription(16, 16, Imf::ONE_LEVEL));
                 image.parts.at(0).header.setType(Imf::TILEDIMAGE);
             });
             patchBox(e.at("frame.exr"), "dataWindow", 0, 0, 99999, 99999);
         },
         {},
         true});
    add({"pass_file_with_a_huge_data_window",
         PP + O,
         3,
         Expect::Error,
         {"pp.depth.exr", "dataWindow||data window"},
         [](const Env& e) { patchBox(e.at("pp.depth.exr"), "dataWindow", -50000, -50000, 49999, 49999); },
         {},
         true});
    add({"header_with_100000_channels_and_no_data",
         composite("{in}/scene.json", "{in}/camera.json", "{in}/wide.exr") + O,
         3,
         Expect::Error,
         {"wide.exr", "channels"},
         [](const Env& e) { writeBytes(e.at("wide.exr"), headerOnlyExr(100000, kWidth, kHeight)); },
         {},
         true});
    add({"png_texture_of_100000_squared",
         C + O,
         3,
         Expect::Error,
         {"scorch.png"},
         [](const Env& e) { patchPngSize(e.at("textures/scorch.png"), 100000, 100000); },
         {},
         true});
    add({"exr_texture_with_a_huge_data_window",
         composite("{in}/scene_volume.json") + O,
         3,
         Expect::Error,
         {"cloud_volume.exr", "dataWindow||data window||too large"},
         [](const Env& e) {
             patchBox(e.at("textures/cloud_volume.exr"), "dataWindow", 0, 0, 99999, 99999);
             writeText(
                 e.at("scene_volume.json"),
                 sceneWith(
                     R"({"name": "cloud", "kind": "volume", "texture": "cloud", "translate": [-1.7, -0.5, 0.5], "scale": 2.2})",
                     R"("textures": {"cloud": {"volume": "textures/cloud_volume.exr", "alpha": "straight"}})"));
         },
         {},
         true});

    // Fuzzing finds, replayed through the CLI (tests/fuzz/regressions): a header OpenEXR's two
    // readers read differently (checks saw 16x16, the decoder allocated 19 GB), and an EXR
    // texture whose header made OpenImageIO allocate gigabytes inside open().
    add({"exr_header_the_two_openexr_readers_read_differently",
         C + O,
         3,
         Expect::Error,
         {"frame.exr", "header"},
         [](const Env& e) { replaceWithFuzzFinding(e.at("frame.exr"), "exr/duplicated-data-window-16M-wide-dwaa.exr"); },
         {},
         true});
    add({"exr_texture_header_that_allocates_on_open",
         composite("{in}/scene_volume.json") + O,
         3,
         Expect::Error,
         {"cloud_volume.exr"},
         [](const Env& e) {
             replaceWithFuzzFinding(e.at("textures/cloud_volume.exr"), "texture/exr-huge-window-allocates-in-open.exr");
             writeText(
                 e.at("scene_volume.json"),
                 sceneWith(
                     R"({"name": "cloud", "kind": "volume", "texture": "cloud", "translate": [-1.7, -0.5, 0.5], "scale": 2.2})",
                     R"("textures": {"cloud": {"volume": "textures/cloud_volume.exr", "alpha": "straight"}})"));
         },
         {},
         true});

    // ---- 3. no silent no-ops: errors ----
    add({"camera_far_before_near", C + O, 3, Expect::Error, {"camera.json", "projection"}, [](const Env& e) {
             setProjection(e, demoProjection(10.0, 1.0));
         }});
    add({"camera_world_to_camera_not_affine",
         C + O,
         3,
         Expect::Error,
         {"camera.json", "world_to_camera"},
         [](const Env& e) {
             editJson(e.at("camera.json"), [](nlohmann::json& j) { j["world_to_camera"][3] = {0.0, 0.0, 0.25, 1.0}; });
         }});
    add({"batch_camera_far_before_near",
         B + BO + " --camera {in}/seq/cam.0001.json",
         3,
         Expect::Error,
         {"cam.0001.json", "projection"},
         [](const Env& e) {
             editJson(e.at("seq/cam.0001.json"), [](nlohmann::json& j) {
                 j["projection"] = matrixJson(glPerspective(49.8, double(kWidth) / kHeight, 50.0, 0.5));
             });
         }});
    // ---- 3. an infinite far plane works ----
    add({"camera_with_infinite_far_plane_works",
         C + O,
         0,
         Expect::Works,
         {},
         [](const Env& e) {
             glm::dmat4 p = demoProjection(0.1, 100.0);
             p[2][2] = -1.0;  // column 2, row 2
             p[3][2] = -0.2;  // column 3, row 2: -2n
             setProjection(e, p);
         },
         r_exr,
         false,
         [](const Env& e) { expectAlbedoChanged(e, "frame.exr", "r.exr"); }});
    // ---- 3. no silent no-ops: warnings ----
    add({"depth_all_background_warns",
         C + O,
         0,
         Expect::Warning,
         {"frame.exr", "background"},
         [](const Env& e) {
             editExr(e.at("frame.exr"), [](ExrImage& image) {
                 fillFloat(channelNamed(image.parts.at(0), "Z"), [](std::size_t) { return INFINITY; });
             });
         },
         r_exr});
    add({"depth_all_nan_warns",
         C + O,
         0,
         Expect::Warning,
         {"frame.exr", "NaN"},
         [](const Env& e) {
             editExr(e.at("frame.exr"), [](ExrImage& image) {
                 fillFloat(channelNamed(image.parts.at(0), "Z"), [](std::size_t) { return NAN; });
             });
         },
         r_exr});
    add({"depth_negative_warns",
         C + O,
         0,
         Expect::Warning,
         {"frame.exr", "negative"},
         [](const Env& e) {
             editExr(e.at("frame.exr"), [](ExrImage& image) {
                 ExrChannel& z = channelNamed(image.parts.at(0), "Z");
                 std::vector<float> old(z.bytes.size() / 4);
                 std::memcpy(old.data(), z.bytes.data(), z.bytes.size());
                 fillFloat(z, [&](std::size_t i) { return -old[i]; });
             });
         },
         r_exr});
    add({"rgb_pass_file_given_as_depth_warns",
         perPass("{in}/scene.json", "{in}/pp.albedo.exr") + O,
         0,
         Expect::Warning,
         {"pp.albedo.exr", "depth"},
         nullptr,
         r_exr});
    add({"object_id_mask_matching_nothing_warns",
         composite("{in}/scene_ids.json") + O,
         0,
         Expect::Warning,
         {"floor_scorch", "mask.ids"},
         [](const Env& e) {
             writeText(e.at("scene_ids.json"), sceneWith(std::string(kScorch) + R"(, "mask": {"ids": [77]}})"));
         },
         r_exr});
    add({"duplicate_decal_names_warn",
         C + O,
         0,
         Expect::Warning,
         {"scene.json", "floor_scorch"},
         [](const Env& e) { sceneFile(e, sceneWith(std::string(kScorch) + "},\n" + kScorch + "}")); },
         r_exr});
    add({"decal_far_from_everything_warns_zero_pixels",
         C + O,
         0,
         Expect::Warning,
         {"scene.json||frame.exr||r.exr"},
         [](const Env& e) {
             sceneFile(e, sceneWith(R"({"name": "far_away", "texture": "scorch", "translate": [500, 500, 500]})"));
         },
         r_exr});
    add({"empty_decal_list_warns_zero_pixels",
         C + O,
         0,
         Expect::Warning,
         {"scene.json||frame.exr||r.exr"},
         [](const Env& e) { sceneFile(e, sceneWith("")); },
         r_exr});

    // ---- 4. one error format: the command line ----
    add({"subcommand_typo_suggests_composite", "compsite {in}/frame.exr", 2, Expect::Error, {"compsite", "composite"}});
    add({"subcommand_typo_suggests_batch", "bacth {in}/seq/frame.####.exr", 2, Expect::Error, {"bacth", "batch"}});
    add({"no_subcommand", "", 2, Expect::Error, {"composite"}});
    add({"unknown_option", C + O + " --previw {out}/p.png", 2, Expect::Error, {"--previw"}});
    add({"missing_required_decals", "composite {in}/frame.exr --device cpu -q" + O, 2, Expect::Error, {"--decals"}});
    add({"missing_option_value", C + " -o", 2, Expect::Error, {"-o||--output"}});
    add({"depth_convention_unknown", C + O + " --depth sideways", 2, Expect::Error, {"--depth", "sideways"}});
    add({"normals_word_unknown", C + O + " --normals world,octahedral", 2, Expect::Error, {"--normals", "octahedral"}});
    add({"pass_attribute_unknown",
         C + O + " --pass colour={in}/pp.albedo.exr",
         2,
         Expect::Error,
         {"--pass", "colour"}});
    add({"channel_flag_without_channels", C + O + " --channel albedo", 2, Expect::Error, {"--channel", "albedo"}});
    add({"add_channels_unknown_attribute",
         C + O + " --add-channels shininess",
         2,
         Expect::Error,
         {"--add-channels", "shininess"}});
    add({"batch_queue_out_of_range_is_readable", B + BO + " --queue 100", 2, Expect::Error, {"--queue", "64"}});
    add({"batch_workers_huge_number_is_readable", B + BO + " --workers 1e400", 2, Expect::Error, {"--workers"}});
    add({"batch_threads_not_a_number", B + BO + " --threads many", 2, Expect::Error, {"--threads", "many"}});
    add({"batch_frames_malformed",
         "batch {in}/seq/frame.####.exr --decals {in}/seq/static_scene.json --device cpu -q "
         "--frames 1-x" +
             BO,
         2,
         Expect::Error,
         {"--frames", "1-x"}});
    add({"batch_shard_beyond_count", B + BO + " --shard 3/2", 2, Expect::Error, {"--shard", "3/2"}});
    add({"batch_output_without_frame_token", B + " -o {out}/c.exr", 2, Expect::Error, {"c.exr"}});
    add({"device_that_does_not_exist",
         "composite {in}/frame.exr --decals {in}/scene.json --camera {in}/camera.json --device nosuchdevice -q" + O,
         4,
         Expect::Error,
         {"nosuchdevice"}});

    // ---- 4. a directory where a file is expected ----
    add({"input_is_a_directory",
         composite("{in}/scene.json", "{in}/camera.json", "{in}/textures") + O,
         3,
         Expect::Error,
         {"textures", "directory||folder"}});
    add({"scene_is_a_directory", composite("{in}/textures") + O, 3, Expect::Error, {"textures", "directory||folder"}});
    add({"camera_is_a_directory",
         composite("{in}/scene.json", "{in}/textures") + O,
         3,
         Expect::Error,
         {"textures", "directory||folder"}});
    add({"pass_file_is_a_directory",
         perPass("{in}/scene.json", "{in}/textures") + O,
         3,
         Expect::Error,
         {"textures", "directory||folder"}});
    add({"profile_file_is_a_directory",
         C + " --profile-file {in}/textures" + O,
         3,
         Expect::Error,
         {"textures", "directory||folder"}});
    add({"texture_is_a_directory", C + O, 3, Expect::Error, {"folder.png", "directory||folder"}, [](const Env& e) {
             fs::create_directories(e.at("textures/folder.png"));
             sceneFile(e, sceneWith(std::string(kScorch) + "}", R"("textures": {"scorch": "textures/folder.png"})"));
         }});

    // ---- 4. JSON numbers out of range, bad fields ----
    add({"scene_opacity_1e400", C + O, 3, Expect::Error, {"scene.json", "decals[0].opacity"}, [](const Env& e) {
             sceneFile(e, sceneWith(std::string(kScorch) + R"(, "opacity": 1e400})"));
         }});
    add({"scene_translate_minus_1e400",
         C + O,
         3,
         Expect::Error,
         {"scene.json", "decals[0].translate"},
         [](const Env& e) {
             sceneFile(e, sceneWith(R"({"name": "floor_scorch", "texture": "scorch", "translate": [-1e400, 0, 0]})"));
         }});
    add({"scene_priority_beyond_int", C + O, 3, Expect::Error, {"scene.json", "decals[0].priority"}, [](const Env& e) {
             sceneFile(e, sceneWith(std::string(kScorch) + R"(, "priority": 1e30})"));
         }});
    add({"scene_occlusion_resolution_overflows",
         C + O,
         3,
         Expect::Error,
         {"scene.json", "decals[0].occlusion.resolution"},
         [](const Env& e) {
             sceneFile(e, sceneWith(R"({"name": "burst", "kind": "cube", "texture": {"cube": "textures/scorch.png"},
                 "translate": [0.2, 0.5, 0.2], "scale": 4.4, "occlusion": {"resolution": 99999999999999999999}})"));
         }});
    add({"camera_projection_1e400", C + O, 3, Expect::Error, {"camera.json", "projection"}, [](const Env& e) {
             std::string text = test::readFileBytes(e.at("camera.json"));
             nlohmann::json j = nlohmann::json::parse(text);
             j["projection"][0][0] = 123456.75;  // a marker, replaced by the literal below
             text = j.dump(2);
             text.replace(text.find("123456.75"), 9, "1e400");
             writeText(e.at("camera.json"), text);
         }});
    add({"scene_opacity_wrong_type", C + O, 3, Expect::Error, {"scene.json", "decals[0].opacity"}, [](const Env& e) {
             sceneFile(e, sceneWith(std::string(kScorch) + R"(, "opacity": "high"})"));
         }});
    add({"scene_key_typo", C + O, 3, Expect::Error, {"scene.json", "decals[0].opactiy", "opacity"}, [](const Env& e) {
             sceneFile(e, sceneWith(std::string(kScorch) + R"(, "opactiy": 0.5})"));
         }});
    add({"scene_truncated_json", C + O, 3, Expect::Error, {"scene.json", "line"}, [](const Env& e) {
             truncateTo(e.at("scene.json"), 60);
         }});
    add({"camera_without_projection", C + O, 3, Expect::Error, {"camera.json", "projection"}, [](const Env& e) {
             editJson(e.at("camera.json"), [](nlohmann::json& j) { j.erase("projection"); });
         }});
    add({"camera_matrix_with_three_rows",
         C + O,
         3,
         Expect::Error,
         {"camera.json", "world_to_camera"},
         [](const Env& e) {
             editJson(e.at("camera.json"), [](nlohmann::json& j) { j["world_to_camera"].erase(3); });
         }});
    add({"profile_file_not_json",
         C + " --profile-file {in}/profile.json" + O,
         3,
         Expect::Error,
         {"profile.json"},
         [](const Env& e) { writeText(e.at("profile.json"), "{\"name\": \"studio\", \"attributes\": "); }});
    add({"profile_file_without_name",
         C + " --profile-file {in}/profile.json" + O,
         3,
         Expect::Error,
         {"profile.json", "name"},
         [](const Env& e) { writeText(e.at("profile.json"), R"({"attributes": {"depth": ["Z"]}})"); }});

    // ---- 4. missing things ----
    add({"missing_input",
         composite("{in}/scene.json", "{in}/camera.json", "{in}/nothere.exr") + O,
         3,
         Expect::Error,
         {"nothere.exr"}});
    add({"missing_scene", composite("{in}/nothere.json") + O, 3, Expect::Error, {"nothere.json"}});
    add({"missing_camera", composite("{in}/scene.json", "{in}/nothere.json") + O, 3, Expect::Error, {"nothere.json"}});
    add({"missing_pass_file", PP + " --pass normal={in}/nothere.exr" + O, 3, Expect::Error, {"nothere.exr"}});
    add({"missing_profile_file", C + " --profile-file {in}/nothere.json" + O, 3, Expect::Error, {"nothere.json"}});
    add({"missing_texture",
         C + O,
         3,
         Expect::Error,
         {"scene.json", "textures.scorch", "nothere.png"},
         [](const Env& e) {
             sceneFile(e, sceneWith(std::string(kScorch) + "}", R"("textures": {"scorch": "textures/nothere.png"})"));
         }});
    add({"missing_depth_pass_suggests_pass_and_channel",
         composite("{in}/scene.json", "{in}/camera.json", "{in}/nodepth.exr") + O,
         3,
         Expect::Error,
         {"nodepth.exr", "depth", "--pass", "--channel"},
         [](const Env& e) {
             fs::copy_file(e.at("frame.exr"), e.at("nodepth.exr"));
             editExr(e.at("nodepth.exr"), [](ExrImage& image) {
                 removeChannels(image.parts.at(0),
                                [](const std::string& n) { return n == "Z" || n.rfind("P.", 0) == 0; });
             });
         }});
    add({"one_channel_file_given_as_position",
         PP + " --pass position={in}/pp.depth.exr" + O,
         3,
         Expect::Error,
         {"pp.depth.exr", "position"}});
    add({"object_id_mask_without_an_id_pass",
         perPass("{in}/scene_ids.json") + O,
         3,
         Expect::Error,
         {"pp.exr||pp.albedo.exr||pp.depth.exr", "object"},
         [](const Env& e) {
             writeText(e.at("scene_ids.json"), sceneWith(std::string(kScorch) + R"(, "mask": {"ids": [1]}})"));
         }});
    add({"channel_flag_naming_absent_channels",
         C + O + " --channel albedo=nope.R,nope.G,nope.B",
         3,
         Expect::Error,
         {"frame.exr", "nope.R"}});

    // ---- 4. broken and truncated EXRs ----
    add({"exr_truncated_to_half", C + O, 3, Expect::Error, {"frame.exr"}, [](const Env& e) {
             truncateTo(e.at("frame.exr"), fs::file_size(e.at("frame.exr")) / 2);
         }});
    add({"exr_truncated_after_the_header", C + O, 3, Expect::Error, {"frame.exr"}, [](const Env& e) {
             truncateTo(e.at("frame.exr"), headerEnd(e.at("frame.exr")));
         }});
    add({"exr_truncated_inside_the_header", C + O, 3, Expect::Error, {"frame.exr"}, [](const Env& e) {
             truncateTo(e.at("frame.exr"), 100);
         }});
    add({"exr_pixel_data_flipped", C + O, 3, Expect::Error, {"frame.exr"}, [](const Env& e) {
             const std::size_t start = headerEnd(e.at("frame.exr")) + 8 * 3 + 64;  // ZIP: 3 chunks of 16 lines
             flipBytes(e.at("frame.exr"), start, 256);
         }});
    add({"exr_offset_table_garbage", C + O, 3, Expect::Error, {"frame.exr"}, [](const Env& e) {
             std::string bytes = test::readFileBytes(e.at("frame.exr"));
             const std::size_t table = headerEnd(e.at("frame.exr"));
             for (int i = 0; i < 3; ++i)
                 putU64(bytes, table + 8 * std::size_t(i), 0x7ffffffffffffff0ull - std::uint64_t(i));
             writeBytes(e.at("frame.exr"), bytes);
         }});
    add({"exr_channel_list_flipped", C + O, 3, Expect::Error, {"frame.exr"}, [](const Env& e) {
             const std::string bytes = test::readFileBytes(e.at("frame.exr"));
             const HeaderAttribute& a = attribute(headerAttributes(bytes), "channels");
             flipBytes(e.at("frame.exr"), a.value_at, a.size);
         }});
    add({"exr_is_a_text_file", C + O, 3, Expect::Error, {"frame.exr", "OpenEXR"}, [](const Env& e) {
             writeText(e.at("frame.exr"), "this is not an image\n");
         }});
    add({"exr_is_empty", C + O, 3, Expect::Error, {"frame.exr"}, [](const Env& e) {
             writeText(e.at("frame.exr"), "");
         }});
    add({"pass_file_truncated", PP + O, 3, Expect::Error, {"pp.depth.exr"}, [](const Env& e) {
             truncateTo(e.at("pp.depth.exr"), fs::file_size(e.at("pp.depth.exr")) / 2);
         }});
    add({"exr_texture_truncated",
         composite("{in}/scene_volume.json") + O,
         3,
         Expect::Error,
         {"cloud_volume.exr"},
         [](const Env& e) {
             truncateTo(e.at("textures/cloud_volume.exr"), fs::file_size(e.at("textures/cloud_volume.exr")) / 2);
             writeText(
                 e.at("scene_volume.json"),
                 sceneWith(
                     R"({"name": "cloud", "kind": "volume", "texture": "cloud", "translate": [-1.7, -0.5, 0.5], "scale": 2.2})",
                     R"("textures": {"cloud": {"volume": "textures/cloud_volume.exr", "alpha": "straight"}})"));
         }});

    // ---- 4. broken PNG textures: named, and no raw libpng lines ----
    add({"png_texture_truncated", C + O, 3, Expect::Error, {"scorch.png"}, [](const Env& e) {
             truncateTo(e.at("textures/scorch.png"), 200);
         }});
    add({"png_texture_crc_error_in_image_data", C + O, 3, Expect::Error, {"scorch.png"}, [](const Env& e) {
             corruptPngData(e.at("textures/scorch.png"));
         }});
    add({"png_texture_is_text", C + O, 3, Expect::Error, {"scorch.png"}, [](const Env& e) {
             writeText(e.at("textures/scorch.png"), "not a png\n");
         }});
    add({"png_texture_ancillary_crc_error_is_not_a_raw_libpng_line",
         C + O,
         0,
         Expect::Works,
         {},
         [](const Env& e) { insertBadTextChunk(e.at("textures/scorch.png")); },
         r_exr});

    // ---- 4. output errors ----
    add({"output_cannot_be_written", C + " -o /proc/decalcomp-matrix.exr", 5, Expect::Error, {"decalcomp-matrix.exr"}});
    add({"preview_cannot_be_written",
         C + O + " --preview /proc/decalcomp-matrix.png",
         5,
         Expect::Error,
         {"decalcomp-matrix.png"}});

    // ---- 5. batch failures ----
    add({"batch_missing_frame_in_range_is_checked_first",
         B + BO,
         3,
         Expect::Error,
         {"frame.0002.exr"},
         [](const Env& e) { fs::remove(e.at("seq/frame.0002.exr")); }});
    add({"batch_missing_last_frame_in_range_is_checked_first",
         B + BO,
         3,
         Expect::Error,
         {"frame.0003.exr"},
         [](const Env& e) { fs::remove(e.at("seq/frame.0003.exr")); }});
    add({"batch_missing_pass_file_in_range_is_checked_first",
         B + " --pass depth={in}/seq/depth.####.exr" + BO,
         3,
         Expect::Error,
         {"depth.0002.exr"},
         [](const Env& e) {
             for (int f : {1, 3})
                 fs::copy_file(e.at(fmt::format("seq/frame.{:04d}.exr", f)),
                               e.at(fmt::format("seq/depth.{:04d}.exr", f)));
         }});
    add({"batch_missing_camera_sidecar_in_range_is_checked_first",
         B + " --camera {in}/seq/cam.####.json" + BO,
         3,
         Expect::Error,
         {"cam.0002.json"},
         [](const Env& e) { fs::remove(e.at("seq/cam.0002.json")); }});
    add({"batch_stops_at_the_first_broken_frame",
         B + BO + " --workers 2",
         3,
         Expect::Error,
         {"frame.0002.exr"},
         [](const Env& e) { truncateTo(e.at("seq/frame.0002.exr"), fs::file_size(e.at("seq/frame.0002.exr")) / 2); },
         {"c.0001.exr"}});
    add({"batch_broken_first_frame_writes_nothing",
         B + BO + " --workers 2",
         3,
         Expect::Error,
         {"frame.0001.exr"},
         [](const Env& e) { truncateTo(e.at("seq/frame.0001.exr"), fs::file_size(e.at("seq/frame.0001.exr")) / 2); }});
    add({"batch_keep_going_past_a_broken_frame",
         B + BO + " --keep-going",
         3,
         Expect::Error,
         {"frame.0002.exr"},
         [](const Env& e) { truncateTo(e.at("seq/frame.0002.exr"), fs::file_size(e.at("seq/frame.0002.exr")) / 2); },
         {"c.0001.exr", "c.0003.exr"}});

    // ---- 6. Cryptomatte ----
    auto cryptoScene = [](const Env& e, const std::string& names) {
        writeText(e.at("scene_crypto.json"),
                  sceneWith(std::string(kScorch) + R"(, "mask": {"cryptomatte": {"names": )" + names + "}}}"));
    };
    const std::string CC = composite("{in}/scene_crypto.json") + O;
    add({"cryptomatte_clean_works",
         CC,
         0,
         Expect::Clean,
         {},
         [=](const Env& e) {
             addCryptomatte(e.at("frame.exr"), {cryptoManifest(), ""});
             cryptoScene(e, R"(["Floor"])");
         },
         r_exr,
         false,
         [](const Env& e) { expectAlbedoChanged(e, "frame.exr", "r.exr"); }});
    add({"cryptomatte_without_manifest_warns_and_keys_by_hash",
         CC,
         0,
         Expect::Warning,
         {"frame.exr", "manifest"},
         [=](const Env& e) {
             addCryptomatte(e.at("frame.exr"), {"", ""});
             cryptoScene(e, R"(["Floor"])");
         },
         r_exr,
         false,
         [](const Env& e) { expectAlbedoChanged(e, "frame.exr", "r.exr"); }});
    add({"cryptomatte_broken_inline_manifest_warns",
         CC,
         0,
         Expect::Warning,
         {"frame.exr", "manifest"},
         [=](const Env& e) {
             addCryptomatte(e.at("frame.exr"), {"{\"Floor\": \"12", ""});
             cryptoScene(e, R"(["Floor"])");
         },
         r_exr,
         false,
         [](const Env& e) { expectAlbedoChanged(e, "frame.exr", "r.exr"); }});
    add({"cryptomatte_missing_manifest_sidecar_warns",
         CC,
         0,
         Expect::Warning,
         {"frame.exr", "nothere.json"},
         [=](const Env& e) {
             addCryptomatte(e.at("frame.exr"), {"", "nothere.json"});
             cryptoScene(e, R"(["Floor"])");
         },
         r_exr,
         false,
         [](const Env& e) { expectAlbedoChanged(e, "frame.exr", "r.exr"); }});
    add({"cryptomatte_broken_manifest_sidecar_warns",
         CC,
         0,
         Expect::Warning,
         {"manifest.json"},
         [=](const Env& e) {
             writeText(e.at("manifest.json"), "[1, 2,");
             addCryptomatte(e.at("frame.exr"), {"", "manifest.json"});
             cryptoScene(e, R"(["Floor"])");
         },
         r_exr,
         false,
         [](const Env& e) { expectAlbedoChanged(e, "frame.exr", "r.exr"); }});
    add({"cryptomatte_pattern_matching_nothing_warns",
         CC,
         0,
         Expect::Warning,
         {"floor_scorch", "mask.cryptomatte.names[0]", "Flor*"},
         [=](const Env& e) {
             addCryptomatte(e.at("frame.exr"), {cryptoManifest(), ""});
             cryptoScene(e, R"(["Flor*"])");
         },
         r_exr});
    add({"cryptomatte_nuke_channel_names_work",
         CC,
         0,
         Expect::Works,
         {},
         [=](const Env& e) {
             addCryptomatte(e.at("frame.exr"), {cryptoManifest(), "", {"red", "green", "blue", "alpha"}});
             cryptoScene(e, R"(["Floor"])");
         },
         r_exr,
         false,
         [](const Env& e) { expectAlbedoChanged(e, "frame.exr", "r.exr"); }});
    add({"cryptomatte_unknown_layer", CC, 3, Expect::Error, {"frame.exr", "CryptoAsset"}, [=](const Env& e) {
             addCryptomatte(e.at("frame.exr"), {cryptoManifest(), ""});
             writeText(e.at("scene_crypto.json"),
                       sceneWith(std::string(kScorch) +
                                 R"(, "mask": {"cryptomatte": {"layer": "CryptoAsset", "names": ["Floor"]}}})"));
         }});
    add({"cryptomatte_preview_is_the_manifest_sidecar",
         CC + " --preview {in}/manifest.json",
         2,
         Expect::Error,
         {"manifest.json", "preview"},
         [=](const Env& e) {
             writeText(e.at("manifest.json"), cryptoManifest());
             addCryptomatte(e.at("frame.exr"), {"", "manifest.json"});
             cryptoScene(e, R"(["Floor"])");
         }});
    return v;
}

// ---------------------------------------------------------------------------------------------
// Running one case

std::string expand(std::string args, const Env& e) {
    const std::pair<std::string, std::string> keys[] = {
        {"{in}", e.in().string()}, {"{out}", e.out().string()}, {"{root}", e.root.string()}};
    for (const auto& [key, value] : keys)
        for (auto at = args.find(key); at != std::string::npos; at = args.find(key, at + value.size()))
            args.replace(at, key.size(), value);
    return args;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) out.push_back(line);
    return out;
}

// Every needle (or one of its "||" alternatives) is in `line`.
bool hasNeedles(const std::string& line, const std::vector<std::string>& needles) {
    for (const std::string& needle : needles) {
        bool any = false;
        std::size_t from = 0;
        while (true) {
            const std::size_t bar = needle.find("||", from);
            const std::string option = needle.substr(from, bar == std::string::npos ? std::string::npos : bar - from);
            any |= line.find(option) != std::string::npos;
            if (bar == std::string::npos) break;
            from = bar + 2;
        }
        if (!any) return false;
    }
    return true;
}

// gtest prints a failing case by its name, not as bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

// 4 GiB and 5 CPU seconds for a run that must fail at once. AddressSanitizer reserves terabytes of
// address space for its shadow memory and cannot start under `ulimit -v`: the sanitizer build caps
// the heap through ASan itself instead (an allocation past the cap throws std::bad_alloc, as one
// past the ulimit does).
std::string memoryCap() {
#ifdef DECALCOMP_SANITIZED_BUILD
    const char* options = std::getenv("ASAN_OPTIONS");
    return "ulimit -t 5; ASAN_OPTIONS='" + std::string(options ? options : "") +
           ":allocator_may_return_null=1:max_allocation_size_mb=4096:soft_rss_limit_mb=4096' ";
#else
    return "ulimit -v 4194304; ulimit -t 5; ";
#endif
}

class Matrix : public testing::TestWithParam<Case> {};

TEST_P(Matrix, Case) {
    const Case& c = GetParam();
    test::ScratchDir scratch;
    const Env e{scratch.path()};
    fs::copy(baseInputs(), e.in(), fs::copy_options::recursive);
    fs::create_directories(e.out());
    if (c.setup) c.setup(e);

    const Snapshot before = snapshot(e.root, e.out());
    const std::string args = expand(c.args, e);
    const std::string command = std::string(c.memory_cap ? memoryCap() : "") + test::shellQuote(DECALCOMP_CLI) + " " + args;
    SCOPED_TRACE("decalcomp " + args);
    const CommandResult r = test::runCommand(command);
    const std::string shown = "exit " + std::to_string(r.exit_code) + ", output:\n" + r.output;
    if (std::getenv("DECALCOMP_MATRIX_VERBOSE")) std::cout << "[ output   ] " << shown << "\n";

    // exit code
    EXPECT_EQ(r.exit_code, c.exit_code)
        << (c.memory_cap && r.exit_code != 3 ? "(a hostile size must fail at once: this run has 4 GiB of address space "
                                               "and 5 CPU seconds; exit -1, 137 or 152 means it was killed at a limit) "
                                             : "")
        << shown;

    // one message format
    const std::vector<std::string> printed = lines(r.output);
    std::vector<std::string> errors, warnings;
    for (const std::string& line : printed) {
        if (line.rfind("decalcomp: error: ", 0) == 0)
            errors.push_back(line);
        else if (line.rfind("decalcomp: warning: ", 0) == 0)
            warnings.push_back(line);
        else
            ADD_FAILURE() << "a line in neither format (decalcomp: error: / decalcomp: warning: ): " << line << "\n"
                          << shown;
    }
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << shown;
    EXPECT_EQ(r.output.find("libpng"), std::string::npos) << shown;
    EXPECT_FALSE(std::regex_search(r.output, std::regex("[0-9]{40}"))) << "an unreadable number: " << shown;
    const auto withNeedles = [&](const std::vector<std::string>& candidates) {
        for (const std::string& line : candidates)
            if (hasNeedles(line, c.needles)) return true;
        return false;
    };
    std::string needles;
    for (const std::string& n : c.needles) needles += " [" + n + "]";
    switch (c.expect) {
        case Expect::Error:
            EXPECT_FALSE(errors.empty()) << "no 'decalcomp: error: ' line; " << shown;
            EXPECT_TRUE(withNeedles(errors)) << "no error line names" << needles << "; " << shown;
            break;
        case Expect::Warning:
            EXPECT_TRUE(errors.empty()) << shown;
            EXPECT_TRUE(withNeedles(warnings)) << "no warning line names" << needles << "; " << shown;
            break;
        case Expect::Works:
            EXPECT_TRUE(errors.empty()) << shown;
            break;
        case Expect::Clean:
            EXPECT_TRUE(printed.empty()) << shown;
            break;
    }

    // nothing left in the output folder but the expected outputs; no temporaries
    const std::set<std::string> left = listTree(e.out());
    EXPECT_EQ(left, c.outputs) << "the output folder holds " << joined(left) << ", expected " << joined(c.outputs)
                               << "; " << shown;

    // every input unchanged, nothing appeared beside them
    const std::string difference = snapshotDifference(before, snapshot(e.root, e.out()));
    EXPECT_TRUE(difference.empty()) << "inputs changed:\n" << difference << shown;

    if (c.verify) c.verify(e);
}

INSTANTIATE_TEST_SUITE_P(BadInputs, Matrix, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& param_info) { return param_info.param.name; });

// The generator is a user-facing tool too: its numeric bounds are readable (CLI11's
// PositiveNumber prints DBL_MAX as a 309-digit number).
TEST(BadInputsMatrix, GeneratorNumericBoundsAreReadable) {
    test::ScratchDir dir;
    const CommandResult r = test::runGenerator("--ortho 1e999", dir.file("g.exr"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--ortho"), std::string::npos) << r.output;
    EXPECT_FALSE(std::regex_search(r.output, std::regex("[0-9]{40}"))) << "an unreadable number: " << r.output;
    EXPECT_FALSE(fs::exists(dir.file("g.exr")));
}

TEST(BadInputsMatrix, HasAtLeastSixtyCasesWithUniqueNames) {
    const std::vector<Case> all = cases();
    std::set<std::string> names;
    for (const Case& c : all) EXPECT_TRUE(names.insert(c.name).second) << "duplicate case " << c.name;
    EXPECT_GE(all.size(), 60u);
}

}  // namespace
}  // namespace decalcomp
