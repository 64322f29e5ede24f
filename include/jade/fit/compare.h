#pragma once
// compare.png: the photo, the render and a slice of the volume side by side,
// with the per-channel histograms of photo and render and the figures that
// judge them (A, S and D, paper §5.2), so a person sees at a glance whether
// the fit matches the photo's look and not only its mean.

#include "jade/core/image.h"
#include "jade/fit/appearance.h"
#include "jade/render/film.h"
#include "jade/volume/histogram.h"
#include "jade/volume/photo.h"

#include <string>

namespace jade {

struct ComparePanels {
    const Photo& photo;
    const Film& render;
    float exposure = 1.0f;          // render → display (docs/design.md, "Display space")
    const RgbImage8& slice;         // the material as the renderer sees it (contrast applied)
    const RgbHistogram& photo_histogram;
    const RgbHistogram& render_histogram;
    // The figures written on the plots and ticked below them: the ones
    // report.json holds (the render's A and S with the noise's share taken
    // out, docs/design.md, "Appearance"), not the raw histograms' own.
    const Appearance& look;
    std::string render_caption;     // e.g. "render 256 spp, error 0.23"
    std::string slice_caption;      // e.g. "volume slice z = 128"
};

// Three pictures `panel` pixels high (photo with its background dimmed, the
// render display-encoded, the slice), each captioned below, then per channel
// a histogram plot: the photo's as a solid line, the render's as a dotted
// one, A ticked below the axis, and "A photo|render  S photo|render  D" above
// (from `look`). A photo that spans more than a cube side (Photo::span) shows
// its central square one side wide, at the slice's scale.
RgbImage8 compare_image(const ComparePanels& panels, int panel = 256);

}  // namespace jade
