#pragma once
// compare.png: the photo, the render and their per-channel histograms side by
// side, so a person sees at a glance whether the fit matches.

#include "jade/film.h"
#include "jade/histogram.h"
#include "jade/photo.h"

#include <cstdint>
#include <vector>

namespace jade {

struct RgbImage8 {
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels;  // RGB, row 0 at the top
};

// Three panels of `panel` pixels height: the photo (background dimmed), the
// render (display-encoded with `exposure`) and the histograms: per channel,
// the photo's as a solid line and the render's as a dotted one, on a shared
// scale, with each channel's A marked below the axis.
RgbImage8 compare_image(const Photo& photo, const Film& render, float exposure,
                        const RgbHistogram& photo_hist, const RgbHistogram& render_hist,
                        int panel = 256);

}  // namespace jade
