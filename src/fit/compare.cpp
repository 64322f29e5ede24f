#include "jade/fit/compare.h"

#include "jade/core/display.h"
#include "jade/io/text.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace jade {

namespace {

constexpr int kGap = 8;          // between panels
constexpr int kCaption = 22;     // the strip under the pictures
constexpr int kTextSize = 13;
const Rgb8 kBackground{40, 40, 40};
const Rgb8 kText{225, 225, 225};
const Rgb8 kSolid[3] = {Rgb8{255, 70, 70}, Rgb8{70, 230, 70}, Rgb8{90, 130, 255}};
const char* const kChannelName[3] = {"R", "G", "B"};

void put(RgbImage8& img, int x, int y, const Rgb8& c) { img.put(x, y, c); }

// A vertical run between two heights, so consecutive histogram bins join.
void column(RgbImage8& img, int x, int y0, int y1, const Rgb8& c) {
    for (int y = std::min(y0, y1); y <= std::max(y0, y1); ++y) put(img, x, y, c);
}

// A picture of w × h source pixels drawn `height` pixels high at x0 by
// nearest sampling; returns the drawn width.
template <typename PixelAt>
int draw_picture(RgbImage8& img, int x0, int height, int w, int h, PixelAt pixel_at) {
    const int dw = std::max(1, int(std::lround(double(height) * w / std::max(1, h))));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < dw; ++x)
            put(img, x0 + x, y, pixel_at(std::min(w - 1, x * w / dw), std::min(h - 1, y * h / height)));
    return dw;
}

// The figures of one channel in two lines: "R  A photo|render" and
// "S photo|render  D".
std::array<std::string, 2> channel_figures(int c, const Appearance& look) {
    char a[64], b[64];
    std::snprintf(a, sizeof a, "%s  A %.1f|%.1f", kChannelName[c], look.a_photo[c], look.a_render[c]);
    std::snprintf(b, sizeof b, "   S %.1f|%.1f  D %.4f", look.s_photo[c], look.s_render[c], look.d[c]);
    return {a, b};
}

// One channel's plot in the box (x0, y0, 256 wide, h high): x = level; y =
// proportion, scaled to the larger peak but at most twice the photo's, so a
// spike in the render (a clipped highlight) does not flatten the photo's curve.
void draw_histogram(RgbImage8& img, int x0, int y0, int h, int c, const RgbHistogram& photo,
                    const RgbHistogram& render, const Appearance& look) {
    const int top = y0 + 2 * kTextSize + 10, base = y0 + h - 12;
    double photo_peak = 1e-9, render_peak = 1e-9;
    for (int i = 0; i < 256; ++i) {
        photo_peak = std::max(photo_peak, photo.proportion(c, i));
        render_peak = std::max(render_peak, render.proportion(c, i));
    }
    const double peak = std::min(std::max(photo_peak, render_peak), 2.0 * photo_peak);
    auto height = [&](double p) { return std::max(top, base - int(std::lround((base - top) * p / peak))); };
    for (int x = 0; x < 256; ++x) put(img, x0 + x, base + 1, Rgb8{160, 160, 160});
    const Rgb8 solid = kSolid[c];
    const Rgb8 light{std::uint8_t(128 + solid[0] / 2), std::uint8_t(128 + solid[1] / 2),
                     std::uint8_t(128 + solid[2] / 2)};
    int prev_photo = base, prev_render = base;
    for (int i = 0; i < 256; ++i) {
        const int yp = height(photo.proportion(c, i));
        const int yr = height(render.proportion(c, i));
        if (i % 2 == 1) column(img, x0 + i, prev_render, yr, light);  // dotted: every other level
        column(img, x0 + i, prev_photo, yp, solid);
        prev_photo = yp;
        prev_render = yr;
    }
    // A(κ): a tick below the axis, solid for the photo, light for the render.
    const auto tick = [](double a) { return int(std::lround(std::clamp(a, 0.0, 255.0))); };
    const int ap = tick(look.a_photo[c]), ar = tick(look.a_render[c]);
    for (int y = base + 3; y < base + 7; ++y) put(img, x0 + ap, y, solid);
    for (int y = base + 7; y < base + 11; ++y) put(img, x0 + ar, y, light);
    const auto lines = channel_figures(c, look);
    draw_text(img, x0 + 2, y0 + kTextSize + 2, lines[0], kTextSize, solid);
    draw_text(img, x0 + 2, y0 + 2 * kTextSize + 6, lines[1], kTextSize, solid);
}

// The part of the photo its panel shows: where the photo spans more than one
// cube side (Photo::span > 1), the central square one side wide, at the
// scale of the slice beside it; else the whole photo. {x0, y0, w, h}.
std::array<int, 4> photo_window(const Photo& photo) {
    if (!(photo.span > 1.0)) return {0, 0, photo.width, photo.height};
    const std::array<int, 4> box = photo.foreground_box();
    const int side = std::max(1, int(std::lround(std::max(box[2], box[3]) / photo.span)));
    const int w = std::min(side, box[2]), h = std::min(side, box[3]);
    return {box[0] + (box[2] - w) / 2, box[1] + (box[3] - h) / 2, w, h};
}

}  // namespace

RgbImage8 compare_image(const ComparePanels& p, int panel) {
    const Photo& photo = p.photo;
    const Film& render = p.render;
    const RgbImage8& slice = p.slice;
    auto width_at = [&](int w, int h) { return std::max(1, int(std::lround(double(panel) * w / std::max(1, h)))); };
    const std::array<int, 4> window = photo_window(photo);
    const int pw = width_at(window[2], window[3]), rw = width_at(render.width(), render.height()),
              sw = width_at(slice.width, slice.height);
    const int plot_height = 170;
    RgbImage8 img;
    const int legend_width = 170;  // "structure 0.00+-0.00" in 13-px DejaVu Sans Mono
    img.width = std::max(pw + rw + sw + 2 * kGap, 3 * (256 + kGap) + legend_width);
    img.height = panel + kCaption + plot_height;
    img.pixels.assign(std::size_t(img.width) * img.height * 3, kBackground[0]);

    int x = 0;
    draw_picture(img, x, panel, window[2], window[3], [&](int sx, int sy) {
        const std::size_t i = std::size_t(sy + window[1]) * photo.width + std::size_t(sx + window[0]);
        Rgb8 c = photo.levels[i];
        if (!photo.foreground[i])  // background dimmed to a quarter
            for (auto& v : c) v = std::uint8_t(v / 4);
        return c;
    });
    char photo_caption[48] = "photo";
    if (photo.span > 1.0) std::snprintf(photo_caption, sizeof photo_caption, "photo, 1/%g of its width", photo.span);
    draw_text(img, x + 4, panel + kCaption - 6, photo_caption, kTextSize, kText);
    x += pw + kGap;
    draw_picture(img, x, panel, render.width(), render.height(), [&](int sx, int sy) {
        const Spectrum m = render.mean(sx, sy) * p.exposure;
        return Rgb8{display_level(m[0]), display_level(m[1]), display_level(m[2])};
    });
    draw_text(img, x + 4, panel + kCaption - 6, p.render_caption, kTextSize, kText);
    x += rw + kGap;
    draw_picture(img, x, panel, slice.width, slice.height, [&](int sx, int sy) {
        const std::uint8_t* s = &slice.pixels[(std::size_t(sy) * slice.width + sx) * 3];
        return Rgb8{s[0], s[1], s[2]};
    });
    draw_text(img, x + 4, panel + kCaption - 6, p.slice_caption, kTextSize, kText);

    for (int c = 0; c < 3; ++c)
        draw_histogram(img, c * (256 + kGap), panel + kCaption, plot_height, c, p.photo_histogram,
                       p.render_histogram, p.look);
    const int lx = 3 * (256 + kGap), ly = panel + kCaption + kTextSize + 2;
    draw_text(img, lx, ly, "solid: photo", kTextSize, kText);
    draw_text(img, lx, ly + kTextSize + 4, "dotted: render", kTextSize, kText);
    draw_text(img, lx, ly + 2 * (kTextSize + 4), "photo|render", kTextSize, kText);
    draw_text(img, lx, ly + 4 * (kTextSize + 4), "ticks: A", kTextSize, kText);
    // The structure (docs/design.md, "Appearance"): the spectra's distance,
    // and each image's dominant direction and how strongly it holds.
    const TextureSpectrum &ps = p.look.photo, &rs = p.look.render;
    char line[48];
    if (p.look.structure >= 0.0)
        std::snprintf(line, sizeof line, "structure %.2f+-%.2f", p.look.structure, p.look.structure_error);
    else
        std::snprintf(line, sizeof line, "structure none");
    draw_text(img, lx, ly + 6 * (kTextSize + 4), line, kTextSize, kText);
    std::snprintf(line, sizeof line, "angle %.0f|%.0f", ps.orientation, rs.orientation);
    draw_text(img, lx, ly + 7 * (kTextSize + 4), line, kTextSize, kText);
    std::snprintf(line, sizeof line, "strength %.2f|%.2f", ps.strength, rs.strength);
    draw_text(img, lx, ly + 8 * (kTextSize + 4), line, kTextSize, kText);
    return img;
}

}  // namespace jade
