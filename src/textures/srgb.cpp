#include <algorithm>
#include <cmath>

#include "decalcomp/textures.hpp"

namespace decalcomp {

// The exact piecewise sRGB curves (IEC 61966-2-1), evaluated in double so that the float result
// is correctly rounded; 8-bit textures go through a table built from this function.
float srgbToLinear(float encoded) {
    const double c = encoded;
    if (c <= 0.04045) return static_cast<float>(c / 12.92);
    return static_cast<float>(std::pow((c + 0.055) / 1.055, 2.4));
}

float linearToSrgb(float linear) {
    const double l = linear;
    if (l <= 0.0031308) return static_cast<float>(l * 12.92);
    return static_cast<float>(1.055 * std::pow(l, 1.0 / 2.4) - 0.055);
}

unsigned char linearToSrgbByte(float linear) {
    const float encoded = linearToSrgb(std::clamp(std::isfinite(linear) ? linear : 0.0f, 0.0f, 1.0f));
    return static_cast<unsigned char>(encoded * 255.0f + 0.5f);
}

}  // namespace decalcomp
