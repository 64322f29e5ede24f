// Display space against the sRGB standard (IEC 61966-2-1).

#include "jade/core/display.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jade;

TEST_CASE("sRGB encoding follows IEC 61966-2-1 and inverts exactly", "[display]") {
    // The two pieces meet at linear 0.0031308, encoded 0.04045.
    CHECK(srgb_encode(0.0031308) == Approx(0.04045).epsilon(1e-4));
    CHECK(srgb_encode(0.001) == Approx(0.01292));
    // Mid grey: 1.055 · 0.5^(1/2.4) − 0.055 = 0.7353570.
    CHECK(srgb_encode(0.5) == Approx(0.7353570).epsilon(1e-6));
    CHECK(srgb_encode(2.0) == Approx(1.0));
    CHECK(srgb_encode(-1.0) == 0.0);
    for (double x : {0.0, 0.002, 0.05, 0.3, 0.9, 1.0}) CHECK(srgb_decode(srgb_encode(x)) == Approx(x).margin(1e-12));
}

TEST_CASE("display levels round the encoded value, and the object rule is one threshold", "[display]") {
    CHECK(display_level(0.0) == 0);
    CHECK(display_level(1.0) == 255);
    CHECK(display_level(7.5) == 255);  // clipped, as a camera would
    CHECK(display_level(0.5) == 188);  // 255 · 0.735357 = 187.5…
    CHECK(display_level(srgb_decode(100.0 / 255.0)) == 100);
    CHECK(level_of_encoded(0.5) == 128);
    CHECK(level_of_encoded(1.2) == 255);
    CHECK(is_object_pixel(0.5f));
    CHECK_FALSE(is_object_pixel(0.49f));
}

TEST_CASE("a level's slope in the log of the radiance is the curve's, and 0 where the clamp holds it",
          "[display]") {
    // Against a central difference of the level in log(x), on both pieces
    // of the curve (the difference's error is O(h²) · the third derivative).
    const double h = 1e-5;
    for (double x : {0.0005, 0.002, 0.01, 0.2, 0.5, 0.9}) {
        const LevelSlope s = continuous_level_slope(x);
        CHECK(s.level == continuous_level(x));
        const double numeric =
            (continuous_level(x * std::exp(h)) - continuous_level(x * std::exp(-h))) / (2.0 * h);
        CHECK(s.slope == Approx(numeric).epsilon(1e-6));
    }
    // The power piece in closed form: 255 · 1.055 / 2.4 · 0.5^(1/2.4) at mid grey.
    CHECK(continuous_level_slope(0.5).slope == Approx(255.0 * 1.055 / 2.4 * std::pow(0.5, 1.0 / 2.4)));
    CHECK(continuous_level_slope(0.0).slope == 0.0);
    CHECK(continuous_level_slope(1.0).slope == 0.0);
    CHECK(continuous_level_slope(3.0).slope == 0.0);
    CHECK(continuous_level_slope(3.0).level == Approx(255.0));
}
