#include "jade/fit/plot.h"

#include "jade/io/text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace jade {

namespace {

constexpr int kText = 13;
// DejaVu Sans Mono's advance width, 0.602 em (io/text's font), which the
// renderer's hinting rounds up to whole pixels (8 px at 13 px): a label's
// width, for placing the legend so that its longest label fits.
constexpr double kMonoAdvance = 0.602;
constexpr int kLeft = 70, kRight = 20, kTop = 46, kBottom = 48;  // margins around the plot area
const Rgb8 kBackground{40, 40, 40};
const Rgb8 kInk{225, 225, 225};
const Rgb8 kGrid{75, 75, 75};

void put(RgbImage8& img, int x, int y, const Rgb8& c) { img.put(x, y, c); }

// A line two pixels wide from (x0, y0) to (x1, y1); dashed: 6 on, 4 off,
// counted along the line from `phase`. Returns the phase at its end.
double line(RgbImage8& img, double x0, double y0, double x1, double y1, const Rgb8& c, bool dashed, double phase) {
    const double len = std::hypot(x1 - x0, y1 - y0);
    const int steps = std::max(1, int(std::ceil(len * 2)));
    for (int i = 0; i <= steps; ++i) {
        const double t = double(i) / steps, along = phase + t * len;
        if (dashed && std::fmod(along, 10.0) >= 6.0) continue;
        const int x = int(std::lround(x0 + t * (x1 - x0))), y = int(std::lround(y0 + t * (y1 - y0)));
        put(img, x, y, c);
        put(img, x, y + 1, c);
    }
    return phase + len;
}

// One axis: its range over the values, mapped onto [p0, p1] pixels.
struct Axis {
    bool log = false;
    double lo = 0, hi = 1;
    double p0 = 0, p1 = 1;
    double value(double v) const { return log ? std::log10(v) : v; }
    double pixel(double v) const { return p0 + (value(v) - lo) / (hi - lo) * (p1 - p0); }
    bool usable(double v) const { return std::isfinite(v) && (!log || v > 0); }
};

Axis make_axis(std::vector<double> values, bool log, double p0, double p1) {
    Axis a{log, 0, 1, p0, p1};
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double v : values)
        if (a.usable(v)) {
            lo = std::min(lo, a.value(v));
            hi = std::max(hi, a.value(v));
        }
    if (!std::isfinite(lo)) lo = 0, hi = 1;
    if (hi - lo < 1e-12) lo -= 0.5, hi += 0.5;
    const double pad = log ? 0.05 * (hi - lo) : 0.05 * (hi - lo);
    a.lo = lo - pad;
    a.hi = hi + pad;
    return a;
}

// Tick values inside the axis: powers of ten (log) or 1, 2, 5 × 10^k steps.
std::vector<double> ticks(const Axis& a) {
    std::vector<double> t;
    if (a.log) {
        for (int k = int(std::ceil(a.lo)); k <= int(std::floor(a.hi)); ++k) t.push_back(std::pow(10.0, k));
        if (t.size() < 2)  // less than a decade: 1, 2, 5 within it
            for (int k = int(std::floor(a.lo)); k <= int(std::ceil(a.hi)); ++k)
                for (double m : {2.0, 5.0})
                    if (const double v = m * std::pow(10.0, k); std::log10(v) >= a.lo && std::log10(v) <= a.hi)
                        t.push_back(v);
        std::sort(t.begin(), t.end());
        return t;
    }
    const double raw = (a.hi - a.lo) / 5.0, mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2 * mag : raw / mag < 7.5 ? 5 * mag : 10 * mag;
    for (double v = std::ceil(a.lo / step) * step; v <= a.hi + 1e-9 * step; v += step)
        t.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
    return t;
}

std::string tick_label(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

void draw_axes(RgbImage8& img, const PlotSpec& spec, const Axis& ax, const Axis& ay) {
    for (double t : ticks(ax)) {
        const double x = ax.pixel(t);
        line(img, x, ay.p1, x, ay.p0, kGrid, false, 0);
        draw_text(img, int(x) - 10, int(ay.p0) + kText + 4, tick_label(t), kText, kInk);
    }
    for (double t : ticks(ay)) {
        const double y = ay.pixel(t);
        line(img, ax.p0, y, ax.p1, y, kGrid, false, 0);
        draw_text(img, 4, int(y) + kText / 2 - 1, tick_label(t), kText, kInk);
    }
    line(img, ax.p0, ay.p0, ax.p1, ay.p0, kInk, false, 0);
    line(img, ax.p0, ay.p0, ax.p0, ay.p1, kInk, false, 0);
    draw_text(img, kLeft, kText + 4, spec.title, kText + 2, kInk);
    draw_text(img, int((ax.p0 + ax.p1) / 2) - 4 * int(spec.x_label.size()), img.height - 6, spec.x_label, kText, kInk);
    draw_text(img, 4, kTop - 12, spec.y_label, kText, kInk);
}

}  // namespace

RgbImage8 line_plot(const PlotSpec& spec) {
    RgbImage8 img{spec.width, spec.height, {}};
    img.pixels.resize(std::size_t(img.width) * img.height * 3);
    for (std::size_t i = 0; i < img.pixels.size(); i += 3) {
        img.pixels[i] = kBackground[0];
        img.pixels[i + 1] = kBackground[1];
        img.pixels[i + 2] = kBackground[2];
    }
    std::vector<double> xs, ys = spec.y_rules;
    for (const PlotSeries& s : spec.series) {
        xs.insert(xs.end(), s.x.begin(), s.x.end());
        ys.insert(ys.end(), s.y.begin(), s.y.end());
    }
    const Axis ax = make_axis(xs, spec.log_x, kLeft, spec.width - kRight);
    const Axis ay = make_axis(ys, spec.log_y, spec.height - kBottom, kTop);
    draw_axes(img, spec, ax, ay);
    for (double r : spec.y_rules)
        if (ay.usable(r)) line(img, ax.p0, ay.pixel(r), ax.p1, ay.pixel(r), Rgb8{150, 150, 150}, true, 0);
    int legend_y = kTop + kText;
    std::size_t longest = 0;
    for (const PlotSeries& s : spec.series) longest = std::max(longest, s.label.size());
    const int lx = spec.width - kRight - 34 - int(std::ceil(kMonoAdvance * kText)) * int(longest);
    for (const PlotSeries& s : spec.series) {
        double phase = 0;
        bool have = false;
        double px = 0, py = 0;
        for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            if (!ax.usable(s.x[i]) || !ay.usable(s.y[i])) continue;
            const double x = ax.pixel(s.x[i]), y = ay.pixel(s.y[i]);
            if (have) phase = line(img, px, py, x, y, s.colour, s.dashed, phase);
            for (int dy = -1; dy <= 1; ++dy)  // a mark on each point
                for (int dx = -1; dx <= 1; ++dx) put(img, int(x) + dx, int(y) + dy, s.colour);
            px = x, py = y, have = true;
        }
        if (s.label.empty()) continue;
        line(img, lx, legend_y - 4, lx + 24, legend_y - 4, s.colour, s.dashed, 0);
        draw_text(img, lx + 30, legend_y, s.label, kText, kInk);
        legend_y += kText + 6;
    }
    return img;
}

}  // namespace jade
