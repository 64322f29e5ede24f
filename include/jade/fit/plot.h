#pragma once
// Line charts for the reports a person looks at: the render's error against
// its run time (convergence.png, log–log with the 1/√t line) and the fit's
// ΔA per fitting render (fit.png). Axes with ticks and numbers, a title and a
// legend, drawn into an 8-bit picture (labels through io/text.h).

#include "jade/core/image.h"

#include <string>
#include <vector>

namespace jade {

struct PlotSeries {
    std::vector<double> x, y;  // points; non-finite ones (and, on a log axis, non-positive) are skipped
    Rgb8 colour{255, 255, 255};
    bool dashed = false;
    std::string label;         // in the legend; "" = none
};

struct PlotSpec {
    std::string title, x_label, y_label;
    bool log_x = false, log_y = false;
    std::vector<PlotSeries> series;
    std::vector<double> y_rules;  // horizontal reference lines (e.g. a tolerance), dashed grey
    int width = 640, height = 420;
};

// The chart as a picture. Its axes span the series' points (and the rules);
// a log axis is ticked at powers of ten, a linear one at 1, 2 or 5 × 10^k.
RgbImage8 line_plot(const PlotSpec& spec);

}  // namespace jade
