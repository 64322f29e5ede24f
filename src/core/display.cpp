#include "jade/core/display.h"

#include <algorithm>
#include <cmath>

namespace jade {

namespace {
// IEC 61966-2-1: a linear segment of slope 12.92 below the knee, above it
// (1 + a)·x^(1/γ) − a.
constexpr double kKnee = 0.0031308, kEncodedKnee = 0.04045, kSlope = 12.92, kOffset = 0.055, kGamma = 2.4;
}  // namespace

double srgb_encode(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x <= kKnee ? kSlope * x : (1.0 + kOffset) * std::pow(x, 1.0 / kGamma) - kOffset;
}

double srgb_decode(double y) {
    y = std::clamp(y, 0.0, 1.0);
    return y <= kEncodedKnee ? y / kSlope : std::pow((y + kOffset) / (1.0 + kOffset), kGamma);
}

double continuous_level(double linear) { return 255.0 * srgb_encode(std::clamp(linear, 0.0, 1.0)); }

LevelSlope continuous_level_slope(double linear) {
    if (!(linear > 0.0 && linear < 1.0)) return {continuous_level(linear), 0.0};
    const double level = continuous_level(linear);
    // x·d/dx of 255·srgb_encode(x): the linear segment's is the level
    // itself; the power segment's, 255·(1 + a)/γ·x^(1/γ), is
    // (level + 255·a)/γ, from the level already computed.
    return {level, linear <= kKnee ? level : (level + 255.0 * kOffset) / kGamma};
}

std::uint8_t display_level(double linear) { return std::uint8_t(std::lround(continuous_level(linear))); }

std::uint8_t level_of_encoded(double encoded) {
    return std::uint8_t(std::lround(std::clamp(encoded, 0.0, 1.0) * 255.0));
}

}  // namespace jade
