// Scene JSON: loadScene on the input, then the scene at a few frames (animation).
//
// Scenes name texture files relative to themselves, and a missing texture stops the parser before
// the decals, so the input is written beside tiny stand-ins for every texture in data/ (same
// relative names, channel counts and strip shapes, a few texels each): the decals of the seeds
// parse, and decoding stays cheap (target_texture.cpp fuzzes decoding itself).
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "decalcomp/decal.hpp"
#include "decalcomp/scene.hpp"
#include "fuzz/fuzz_support.hpp"
#include "fuzz/fuzz_targets.hpp"

namespace decalcomp::fuzz {

namespace fs = std::filesystem;

namespace {

bool isDecalTexture(const fs::path& file) {
    const std::string ext = file.extension().string();
    const std::string stem = file.stem().string();
    if (ext != ".png" && ext != ".exr") return false;
    return stem.rfind("gbuffer", 0) != 0 && stem.rfind("truth", 0) != 0;  // frames, not textures
}

// The stand-in's size: strips of squares (cube 6:1, volume 1:D) keep their shape with 2-texel
// squares; anything else is cut to at most 4x4.
void standInSize(int width, int height, int& w, int& h) {
    const int side = std::min(width, height);
    if (side > 0 && width % side == 0 && height % side == 0) {
        w = width / side * 2;
        h = height / side * 2;
    } else {
        w = std::min(width, 4);
        h = std::min(height, 4);
    }
}

void writeStandIn(const fs::path& source, const fs::path& target) {
    auto in = OIIO::ImageInput::open(source.string());
    if (!in) return;
    const OIIO::ImageSpec& original = in->spec();
    int w = 0, h = 0;
    standInSize(original.width, original.height, w, h);
    const bool exr = source.extension() == ".exr";
    OIIO::ImageSpec spec(w, h, original.nchannels, exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    const std::string alpha = original.get_string_attribute("decal:alpha");
    if (exr && !alpha.empty()) spec.attribute("decal:alpha", alpha);
    std::vector<float> texels(std::size_t(w) * std::size_t(h) * std::size_t(original.nchannels));
    for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = float(i % 7) / 6.0f;
    fs::create_directories(target.parent_path());
    auto out = OIIO::ImageOutput::create(target.string());
    if (out && out->open(target.string(), spec)) {
        out->write_image(OIIO::TypeDesc::FLOAT, texels.data());
        out->close();
    }
}

// scratch/scene/ with a stand-in for every texture under data/<set>/, at its path in <set>.
fs::path sceneFolder() {
    static const fs::path folder = [] {
        const fs::path dir = scratchDir() / "scene";
        fs::create_directories(dir);
        const fs::path data(DECALCOMP_DATA_DIR);
        for (const fs::directory_entry& set : fs::directory_iterator(data)) {
            if (!set.is_directory()) continue;
            for (const fs::directory_entry& file : fs::recursive_directory_iterator(set.path()))
                if (file.is_regular_file() && isDecalTexture(file.path()))
                    writeStandIn(file.path(), dir / fs::relative(file.path(), set.path()));
        }
        return dir;
    }();
    return folder;
}

}  // namespace

void fuzzScene(const std::uint8_t* data, std::size_t size) {
    const std::string path = (sceneFolder() / "scene.json").string();
    writeScratchFile(fs::relative(path, scratchDir()).string(), asText(data, size));
    DecalScene scene;
    if (!inputErrorsAllowed([&] { scene = loadScene(path); })) return;
    if (!isAnimated(scene)) return;
    for (double frame : {-1.0, 0.0, 1.0, 1.5, 24.0, 1e6})
        inputErrorsAllowed([&] { (void)sceneAtFrame(scene, frame); });
}

}  // namespace decalcomp::fuzz
