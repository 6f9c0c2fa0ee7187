// Writes the material decal textures of data/sample (deterministic, no inputs):
//   plate.png      riveted metal plate, sRGB albedo, alpha = rounded-rectangle mask
//   plate_n.png    its tangent-space normal map (OpenGL, +Y up; n * 0.5 + 0.5, data)
//   plate_orm.png  its occlusion / roughness / metallic in R / G / B (data)
//   dent_n.png     a dent with cracks, normal map only; alpha = the decal's coverage
// Normals come from analytic height fields by central differences.
// Regenerate: cmake --build <build> --target decalcomp-sample-textures &&
//             <build>/decalcomp-sample-textures data/sample/textures
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace {

constexpr int kSize = 256;
constexpr double kPi = 3.14159265358979323846;

double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }
double smoothstep(double a, double b, double x) {
    const double t = clamp01((x - a) / (b - a));
    return t * t * (3.0 - 2.0 * t);
}
std::uint8_t byte(double v) { return std::uint8_t(std::lround(clamp01(v) * 255.0)); }
double srgb(double linear) {
    linear = clamp01(linear);
    return linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}
// Deterministic hash noise in [0, 1).
double hash(int x, int y) {
    std::uint32_t h = std::uint32_t(x) * 374761393u + std::uint32_t(y) * 668265263u;
    h = (h ^ (h >> 13)) * 1274126177u;
    return double((h ^ (h >> 16)) & 0xffffff) / double(0x1000000);
}

struct Image {
    int channels;
    std::vector<std::uint8_t> data = std::vector<std::uint8_t>(std::size_t(kSize) * kSize * channels);
    std::uint8_t* at(int x, int y) { return &data[(std::size_t(y) * kSize + x) * channels]; }
};

bool save(const Image& img, const std::string& path) {
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec(kSize, kSize, img.channels, OIIO::TypeDesc::UINT8);
    spec.attribute("png:compressionLevel", 9);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // our colour is straight: stop OIIO dividing it by alpha
    if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, img.data.data()) || !out->close()) {
        std::fprintf(stderr, "%s: %s\n", path.c_str(), out ? out->geterror().c_str() : OIIO::geterror().c_str());
        return false;
    }
    std::printf("wrote %s\n", path.c_str());
    return true;
}

// Tangent-space normal of height field h (texel units, x right, y down the rows), OpenGL +Y up.
void normalFromHeight(const std::function<double(double, double)>& h, double x, double y, std::uint8_t* rgb) {
    const double dx = (h(x + 1, y) - h(x - 1, y)) / 2.0, dy = (h(x, y + 1) - h(x, y - 1)) / 2.0;
    const double nx = -dx, ny = dy, nz = 1.0, len = std::sqrt(nx * nx + ny * ny + nz * nz);
    rgb[0] = byte(nx / len * 0.5 + 0.5);
    rgb[1] = byte(ny / len * 0.5 + 0.5);
    rgb[2] = byte(nz / len * 0.5 + 0.5);
}

// ---- plate: rounded rectangle with a bevelled edge, a cross of panel seams, rivets along the border
constexpr double kMargin = 10, kCorner = 28, kBevel = 12, kRivetInset = 24, kRivetRadius = 7.5;
double plateDistance(double x, double y) {  // signed distance to the rounded rectangle (< 0 inside)
    const double c = kSize / 2.0, half = c - kMargin - kCorner;
    const double qx = std::abs(x - c) - half, qy = std::abs(y - c) - half;
    return std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0) - kCorner;
}
double rivetDistance(double x, double y) {  // to the nearest rivet centre
    const double lo = kRivetInset, hi = kSize - kRivetInset, step = (hi - lo) / 6.0;
    double best = 1e9;
    for (int i = 0; i <= 6; ++i)
        for (int j = 0; j <= 6; ++j) {
            if ((i != 0 && i != 6 && j != 0 && j != 6) || i == 3 || j == 3) continue;  // border, off the seams
            best = std::min(best, std::hypot(x - (lo + i * step), y - (lo + j * step)));
        }
    return best;
}
double seamDistance(double x, double y) { return std::min(std::abs(x - kSize / 2.0), std::abs(y - kSize / 2.0)); }
double plateHeight(double x, double y) {
    const double d = plateDistance(x, y);
    double h = 6.0 * smoothstep(0.0, kBevel, -d);                              // bevelled edge
    h -= 3.0 * std::exp(-std::pow(seamDistance(x, y) / 1.8, 2.0)) * smoothstep(kBevel, kBevel + 8, -d);  // seams
    const double q = rivetDistance(x, y) / kRivetRadius;
    if (q < 1.0) h += 5.0 * std::sqrt(1.0 - q * q);                         // dome rivets
    return h;
}

void plate(const std::string& dir, bool& ok) {
    Image albedo{4}, normal{3}, orm{3};
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const double px = x + 0.5, py = y + 0.5, d = plateDistance(px, py);
            const double rivet = rivetDistance(px, py) < kRivetRadius ? 1.0 : 0.0;
            const double seam = std::exp(-std::pow(seamDistance(px, py) / 2.5, 2.0)) * smoothstep(kBevel, kBevel + 8, -d);
            const double edge = 1.0 - smoothstep(0.0, 40.0, -d);                // grime towards the rim
            const double brushed = 0.04 * (hash(y, 7) - 0.5);                   // one value per row: streaks
            double base = 0.30 + brushed + 0.10 * rivet - 0.12 * edge - 0.15 * seam;
            std::uint8_t* a = albedo.at(x, y);
            a[0] = byte(srgb(base * 0.95));
            a[1] = byte(srgb(base * 0.98));
            a[2] = byte(srgb(base * 1.05));
            a[3] = byte(0.5 - d);  // antialiased mask
            normalFromHeight(plateHeight, px, py, normal.at(x, y));
            const double rim = std::exp(-std::pow((rivetDistance(px, py) - kRivetRadius) / 1.5, 2.0));
            std::uint8_t* o = orm.at(x, y);
            o[0] = byte(1.0 - 0.4 * seam - 0.3 * rim);                         // occlusion
            o[1] = byte(0.28 + 0.25 * edge + 0.4 * seam - 0.12 * rivet);       // roughness: low on metal
            o[2] = 255;                                                        // metallic
        }
    ok &= save(albedo, dir + "/plate.png");
    ok &= save(normal, dir + "/plate_n.png");
    ok &= save(orm, dir + "/plate_orm.png");
}

// ---- dent: a smooth crater with a raised rim and radial cracks; alpha fades out towards the edge
double crackDistance(double x, double y) {
    const double c = kSize / 2.0, dx = x - c, dy = y - c, r = std::hypot(dx, dy);
    double best = 1e9;
    for (int k = 0; k < 7; ++k) {
        const double angle = 2.0 * kPi * (k + 0.6 * hash(k, 1)) / 7.0;
        const double length = 70.0 + 40.0 * hash(k, 2);
        if (r > length) continue;
        const double wobble = (0.10 * std::sin(r * 0.13 + 2 * k) + 0.05 * std::sin(r * 0.41 + k)) * (r / length);  // jagged
        const double a = angle + wobble, ux = std::cos(a), uy = std::sin(a);
        const double along = dx * ux + dy * uy, across = std::abs(-dx * uy + dy * ux);
        if (along > 0) best = std::min(best, across / (1.0 - r / length + 0.15));  // tapers
    }
    return best;
}
double dentHeight(double x, double y) {
    const double r = std::hypot(x - kSize / 2.0, y - kSize / 2.0);
    double h = -14.0 * std::exp(-std::pow(r / 38.0, 2.0)) + 4.0 * std::exp(-std::pow((r - 58.0) / 12.0, 2.0));
    h -= 3.0 * std::exp(-std::pow(crackDistance(x, y) / 1.5, 2.0));
    return h;
}
void dent(const std::string& dir, bool& ok) {
    Image normal{4};
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const double px = x + 0.5, py = y + 0.5, r = std::hypot(px - kSize / 2.0, py - kSize / 2.0);
            std::uint8_t* n = normal.at(x, y);
            normalFromHeight(dentHeight, px, py, n);
            n[3] = byte(1.0 - smoothstep(90.0, 124.0, r));
        }
    ok &= save(normal, dir + "/dent_n.png");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUTPUT_DIR   (e.g. data/sample/textures)\n", argv[0]);
        return 2;
    }
    bool ok = true;
    plate(argv[1], ok);
    dent(argv[1], ok);
    return ok ? 0 : 1;
}
