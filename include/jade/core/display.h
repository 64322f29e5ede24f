#pragma once
// Display space: where the photo lives and where renders are compared with it
// (docs/design.md, "Display space"). One place for the sRGB transfer function,
// for turning linear radiance into the 8-bit levels the method works in, and
// for the rule that says which pixels of a render show the object.

#include <cstdint>

namespace jade {

// sRGB transfer function (IEC 61966-2-1), linear [0,1] → encoded [0,1]
// (clamped), and its inverse.
double srgb_encode(double linear);
double srgb_decode(double encoded);

// Linear radiance (already multiplied by its exposure) → 8-bit display level:
// clamped to [0, 1], sRGB-encoded, rounded.
std::uint8_t display_level(double linear);
// The same level before rounding (statistics over many pixels: means and
// spreads of levels without the rounding's steps).
double continuous_level(double linear);
// The same level and its derivative with respect to log(linear): how fast
// the level rises as the radiance is scaled (0 where the clamp holds it).
struct LevelSlope {
    double level, slope;
};
LevelSlope continuous_level_slope(double linear);
// An already-encoded value in [0, 1] (an 8-bit or 16-bit file's) → level.
std::uint8_t level_of_encoded(double encoded);

// The brightness of a displayed colour, for measures of structure: Rec. 709
// weights applied to the display levels (luma, not linear luminance).
inline double luma(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// A render pixel shows the object when at least half of its camera rays met
// it: the fit's histograms, compare.png and the error estimate all use this.
constexpr float kObjectCoverage = 0.5f;
inline bool is_object_pixel(float coverage) { return coverage >= kObjectCoverage; }

}  // namespace jade
