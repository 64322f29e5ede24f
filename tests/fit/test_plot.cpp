// The line charts of the reports: points land where their axes say, log
// axes are ticked at powers of ten, and rules and dashes are drawn.

#include "jade/fit/plot.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace jade;

namespace {

bool has_colour(const RgbImage8& img, int x0, int y0, int x1, int y1, const Rgb8& c) {
    for (int y = std::max(0, y0); y <= std::min(img.height - 1, y1); ++y)
        for (int x = std::max(0, x0); x <= std::min(img.width - 1, x1); ++x) {
            const std::uint8_t* p = &img.pixels[(std::size_t(y) * img.width + x) * 3];
            if (p[0] == c[0] && p[1] == c[1] && p[2] == c[2]) return true;
        }
    return false;
}

}  // namespace

TEST_CASE("a line chart puts its points where its axes say", "[plot]") {
    const Rgb8 red{250, 10, 10}, blue{10, 10, 250};
    PlotSpec spec;
    spec.width = 400;
    spec.height = 300;
    // Linear: a rising line from (0, 0) to (10, 10), and a flat one at y = 5.
    spec.series = {PlotSeries{{0, 10}, {0, 10}, red, false, ""}, PlotSeries{{0, 10}, {5, 5}, blue, true, ""}};
    const RgbImage8 img = line_plot(spec);
    REQUIRE(img.width == 400);
    REQUIRE(img.height == 300);
    // The plot area spans x 70..380 and y 252..46 (the margins), the data 5% inside it.
    const double x_mid = 70 + 0.5 * (380 - 70), y_mid = 252 + 0.5 * (46 - 252);
    CHECK(has_colour(img, int(x_mid) - 2, int(y_mid) - 2, int(x_mid) + 2, int(y_mid) + 2, red));  // (5, 5)
    CHECK(has_colour(img, 90, int(y_mid) - 2, 380, int(y_mid) + 2, blue));                        // y = 5 across
    // Dashed: some pixels of the flat line's row are not blue.
    int gaps = 0;
    for (int x = 100; x < 360; ++x) gaps += has_colour(img, x, int(y_mid) - 1, x, int(y_mid) + 2, blue) ? 0 : 1;
    CHECK(gaps > 20);
    // Nothing drawn in the top-left corner of the plot area (the line rises from bottom-left).
    CHECK_FALSE(has_colour(img, 75, 50, 120, 90, red));
}

TEST_CASE("log axes: a 1/sqrt(t) series is a straight line, and non-positive points are skipped", "[plot]") {
    const Rgb8 green{10, 240, 10};
    PlotSpec spec;
    spec.log_x = spec.log_y = true;
    PlotSeries s{{}, {}, green, false, "1/sqrt(t)"};
    for (double t : {0.01, 0.1, 1.0, 10.0, 100.0}) {
        s.x.push_back(t);
        s.y.push_back(1.0 / std::sqrt(t));
    }
    s.x.push_back(-1.0);  // skipped: no logarithm
    s.y.push_back(1.0);
    spec.series = {s};
    const RgbImage8 img = line_plot(spec);
    // On log-log axes the points lie on a line: the middle point (t = 1)
    // sits halfway between the ends, in x and in y.
    const double x0 = 70, x1 = 640 - 20, y0 = 420 - 48, y1 = 46;
    const double xm = x0 + 0.5 * (x1 - x0), ym = y0 + 0.5 * (y1 - y0);
    CHECK(has_colour(img, int(xm) - 2, int(ym) - 2, int(xm) + 2, int(ym) + 2, green));
    // Rules (a tolerance band) widen the range to include them.
    PlotSpec ruled;
    ruled.series = {PlotSeries{{0, 1}, {0, 0}, green, false, ""}};
    ruled.y_rules = {-1, 1};
    const RgbImage8 band = line_plot(ruled);
    const Rgb8 grey{150, 150, 150};
    CHECK(has_colour(band, 100, 46, 600, 100, grey));   // the +1 rule near the top
    CHECK(has_colour(band, 100, 320, 600, 372, grey));  // the -1 rule near the bottom
}

TEST_CASE("the legend moves left so that its longest label ends inside the picture", "[plot]") {
    // DejaVu Sans Mono at 13 px advances 8 px a character (0.602 em, hinted
    // to whole pixels): a 48-character label is 384 px wide, more than the
    // 250 px a fixed legend once left.
    const Rgb8 green{20, 220, 20};
    PlotSpec spec;
    spec.series = {PlotSeries{{1, 2}, {1, 2}, green, false, std::string(48, 'W')}};
    const RgbImage8 img = line_plot(spec);
    const std::uint8_t* corner = &img.pixels[(std::size_t(0) * img.width + img.width - 1) * 3];
    const Rgb8 background{corner[0], corner[1], corner[2]};
    // The right margin beside the legend's line of text is untouched.
    bool margin_clear = true;
    for (int y = 40; y < 70; ++y)
        for (int x = img.width - 18; x < img.width; ++x) {
            const std::uint8_t* p = &img.pixels[(std::size_t(y) * img.width + x) * 3];
            margin_clear = margin_clear && p[0] == background[0] && p[1] == background[1] && p[2] == background[2];
        }
    CHECK(margin_clear);
    // Its sample line sits left of the text, 34 px plus the text's width from the margin.
    const int lx = img.width - 20 - 34 - 8 * 48;
    CHECK(has_colour(img, lx, 53, lx + 24, 57, green));
}
