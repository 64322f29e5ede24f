// compare.png: the pictures land where they should and the figures are
// written on it (text drawn by the font fonts-dejavu-core installs).

#include "jade/fit/compare.h"
#include "jade/io/text.h"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace jade;

namespace {

Rgb8 pixel(const RgbImage8& img, int x, int y) {
    const std::uint8_t* p = &img.pixels[(std::size_t(y) * img.width + x) * 3];
    return {p[0], p[1], p[2]};
}

// Pixels in the box [x0, x1) × [y0, y1) that differ from `background`.
int changed(const RgbImage8& img, int x0, int y0, int x1, int y1, const Rgb8& background) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) n += pixel(img, x, y) != background;
    return n;
}

}  // namespace

TEST_CASE("text: drawn inside its line, nothing outside", "[compare]") {
    RgbImage8 img;
    img.width = 200;
    img.height = 40;
    img.pixels.assign(200 * 40 * 3, 40);
    REQUIRE(draw_text(img, 10, 25, "A 145.2|142.7", 13, Rgb8{255, 255, 255}));
    const Rgb8 bg{40, 40, 40};
    CHECK(changed(img, 10, 10, 200, 29, bg) > 50);   // the glyphs
    CHECK(changed(img, 0, 0, 200, 8, bg) == 0);      // above the cap height
    CHECK(changed(img, 0, 30, 200, 40, bg) == 0);    // below the descenders
    CHECK(changed(img, 0, 0, 9, 40, bg) == 0);       // left of the start
}

TEST_CASE("compare image: photo, render and slice side by side, figures on the plots", "[compare]") {
    Photo photo;
    photo.width = photo.height = 64;
    for (int i = 0; i < 64 * 64; ++i) {
        photo.levels.push_back({200, 100, 50});
        photo.foreground.push_back(1);
    }
    Film film(32, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) film.add_sample(x, y, Spectrum(1.f), true);  // white at exposure 1
    RgbImage8 slice;
    slice.width = slice.height = 16;
    slice.pixels.assign(16 * 16 * 3, 0);
    for (std::size_t i = 0; i < slice.pixels.size(); i += 3) slice.pixels[i + 2] = 255;  // blue
    const RgbHistogram ph = RgbHistogram::of(photo.levels);
    const RgbHistogram rh = RgbHistogram::of(std::vector<Rgb8>(10, Rgb8{255, 255, 255}));
    Appearance look;  // the figures written on the plots
    for (int c = 0; c < 3; ++c) {
        look.a_photo[c] = ph.mean(c);
        look.a_render[c] = 254.6;
        look.s_photo[c] = 0.0;
        look.s_render[c] = 0.4;
        look.d[c] = histogram_distance(ph, rh, c);
    }
    const RgbImage8 img = compare_image({photo, film, 1.f, slice, ph, rh, look, "render", "slice"}, 100);

    REQUIRE(img.height > 100);
    CHECK(pixel(img, 50, 50) == Rgb8{200, 100, 50});           // photo, 100 px wide
    CHECK(pixel(img, 100 + 8 + 50, 50) == Rgb8{255, 255, 255});  // render
    CHECK(pixel(img, 2 * (100 + 8) + 50, 50) == Rgb8{0, 0, 255}); // slice
    // Each channel's plot has its line of figures above it.
    const Rgb8 bg{40, 40, 40};
    for (int c = 0; c < 3; ++c) CHECK(changed(img, c * (256 + 8), 122, c * (256 + 8) + 256, 160, bg) > 100);
    // The legend's last lines carry the structure: its distance (or none),
    // the photo's and the render's directions and strengths.
    const int lx = 3 * (256 + 8), top = 100 + 22 + 13 + 2 + 6 * (13 + 4) - 13, bottom = top + 3 * (13 + 4) + 4;
    CHECK(changed(img, lx, top, img.width, bottom, bg) > 100);
    look.structure = 0.42;
    look.render.orientation = 90.0;
    const RgbImage8 other = compare_image({photo, film, 1.f, slice, ph, rh, look, "render", "slice"}, 100);
    int differ = 0;
    for (int y = top; y < bottom; ++y)
        for (int x = lx; x < img.width; ++x) differ += pixel(img, x, y) != pixel(other, x, y);
    CHECK(differ > 20);
    // Nothing of it spills below the plots.
    CHECK(changed(img, lx, bottom, img.width, img.height, bg) == 0);
}

TEST_CASE("compare image: a photo spanning four cube sides shows its central square, one side wide",
          "[compare]") {
    // Red, with a blue square of a quarter of its width in its middle: at
    // span 4 the photo's panel is that square alone, at the slice's scale.
    Photo photo;
    photo.width = photo.height = 64;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const bool middle = x >= 24 && x < 40 && y >= 24 && y < 40;
            photo.levels.push_back(middle ? Rgb8{0, 0, 255} : Rgb8{255, 0, 0});
            photo.foreground.push_back(1);
        }
    Film film(32, 32);
    RgbImage8 slice;
    slice.width = slice.height = 16;
    slice.pixels.assign(16 * 16 * 3, 0);
    const RgbHistogram ph = RgbHistogram::of(photo.levels);
    const Appearance look;
    const auto panel_at = [&](double span, int x, int y) {
        photo.span = span;
        return pixel(compare_image({photo, film, 1.f, slice, ph, ph, look, "render", "slice"}, 100), x, y);
    };
    CHECK(panel_at(1.0, 5, 5) == Rgb8{255, 0, 0});
    CHECK(panel_at(1.0, 50, 50) == Rgb8{0, 0, 255});
    CHECK(panel_at(4.0, 5, 5) == Rgb8{0, 0, 255});
    CHECK(panel_at(4.0, 94, 94) == Rgb8{0, 0, 255});
    // A photo narrower than a side is shown whole.
    CHECK(panel_at(0.5, 5, 5) == Rgb8{255, 0, 0});
}
