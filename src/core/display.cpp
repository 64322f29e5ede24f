#include "jade/core/display.h"

#include <algorithm>
#include <cmath>

namespace jade {

double srgb_encode(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

double srgb_decode(double y) {
    y = std::clamp(y, 0.0, 1.0);
    return y <= 0.04045 ? y / 12.92 : std::pow((y + 0.055) / 1.055, 2.4);
}

double continuous_level(double linear) { return 255.0 * srgb_encode(std::clamp(linear, 0.0, 1.0)); }

std::uint8_t display_level(double linear) { return std::uint8_t(std::lround(continuous_level(linear))); }

std::uint8_t level_of_encoded(double encoded) {
    return std::uint8_t(std::lround(std::clamp(encoded, 0.0, 1.0) * 255.0));
}

}  // namespace jade
