#include "jade/fit/compare.h"

#include "jade/core/display.h"

#include <algorithm>
#include <cmath>

namespace jade {

namespace {

void put(RgbImage8& img, int x, int y, const Rgb8& c) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
    std::uint8_t* p = &img.pixels[(std::size_t(y) * img.width + x) * 3];
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
}

// A vertical run between two heights, so consecutive histogram bins join.
void column(RgbImage8& img, int x, int y0, int y1, const Rgb8& c) {
    for (int y = std::min(y0, y1); y <= std::max(y0, y1); ++y) put(img, x, y, c);
}

}  // namespace

RgbImage8 compare_image(const Photo& photo, const Film& render, float exposure,
                        const RgbHistogram& photo_hist, const RgbHistogram& render_hist, int panel) {
    const int pw = std::max(1, int(std::lround(double(panel) * photo.width / photo.height)));
    const int rw = std::max(1, int(std::lround(double(panel) * render.width() / std::max(1, render.height()))));
    const int hw = 2 * panel;
    const int gap = 8;
    RgbImage8 img;
    img.width = pw + rw + hw + 2 * gap;
    img.height = panel;
    img.pixels.assign(std::size_t(img.width) * img.height * 3, 40);

    // Photo, nearest sampling; background pixels dimmed to a quarter.
    for (int y = 0; y < panel; ++y)
        for (int x = 0; x < pw; ++x) {
            const int sx = std::min(photo.width - 1, x * photo.width / pw);
            const int sy = std::min(photo.height - 1, y * photo.height / panel);
            const std::size_t i = std::size_t(sy) * photo.width + sx;
            Rgb8 c = photo.levels[i];
            if (!photo.foreground[i])
                for (auto& v : c) v = std::uint8_t(v / 4);
            put(img, x, y, c);
        }
    // Render, display-encoded.
    for (int y = 0; y < panel; ++y)
        for (int x = 0; x < rw; ++x) {
            const int sx = std::min(render.width() - 1, x * render.width() / rw);
            const int sy = std::min(render.height() - 1, y * render.height() / panel);
            const Spectrum m = render.mean(sx, sy) * exposure;
            Rgb8 c;
            for (int k = 0; k < 3; ++k)
                c[k] = display_level(m[k]);
            put(img, pw + gap + x, y, c);
        }
    // Histograms: x = level (two pixels each), y = proportion, on one scale.
    const int x0 = pw + rw + 2 * gap;
    const int base = panel - 12, top = 8;
    double peak = 1e-9;
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 256; ++i)
            peak = std::max({peak, photo_hist.proportion(c, i), render_hist.proportion(c, i)});
    for (int x = 0; x < hw; ++x) put(img, x0 + x, base + 1, Rgb8{160, 160, 160});
    const Rgb8 solid[3] = {Rgb8{255, 70, 70}, Rgb8{70, 230, 70}, Rgb8{90, 130, 255}};
    auto height = [&](double p) { return base - int(std::lround((base - top) * p / peak)); };
    for (int c = 0; c < 3; ++c) {
        int prev_photo = base, prev_render = base;
        for (int i = 0; i < 256; ++i) {
            const int yp = height(photo_hist.proportion(c, i));
            const int yr = height(render_hist.proportion(c, i));
            column(img, x0 + 2 * i, prev_photo, yp, solid[c]);
            put(img, x0 + 2 * i + 1, yp, solid[c]);
            if (i % 2 == 0) {  // dotted: every other level
                const Rgb8 light{std::uint8_t(128 + solid[c][0] / 2), std::uint8_t(128 + solid[c][1] / 2),
                                 std::uint8_t(128 + solid[c][2] / 2)};
                column(img, x0 + 2 * i + 1, prev_render, yr, light);
            }
            prev_photo = yp;
            prev_render = yr;
        }
        // A(κ): a tick below the axis, solid for the photo, light for the render.
        const int ap = int(std::lround(2 * photo_hist.mean(c))), ar = int(std::lround(2 * render_hist.mean(c)));
        for (int y = base + 3; y < base + 7; ++y) put(img, x0 + ap, y, solid[c]);
        for (int y = base + 7; y < base + 11; ++y) put(img, x0 + ar, y, Rgb8{230, 230, 230});
    }
    return img;
}

}  // namespace jade
