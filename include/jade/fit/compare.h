#pragma once
// compare.png: the photo, the render and their per-channel histograms side by
// side, so a person sees at a glance whether the fit matches.

#include "jade/render/film.h"
#include "jade/volume/histogram.h"
#include "jade/volume/photo.h"

#include <cstdint>
#include <vector>

namespace jade {

// Three panels of `panel` pixels height: the photo (background dimmed), the
// render (display-encoded with `exposure`) and the histograms: per channel,
// the photo's as a solid line and the render's as a dotted one, on a shared
// scale, with each channel's A marked below the axis.
RgbImage8 compare_image(const Photo& photo, const Film& render, float exposure,
                        const RgbHistogram& photo_hist, const RgbHistogram& render_hist,
                        int panel = 256);

}  // namespace jade
