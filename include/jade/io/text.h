#pragma once
// Text on 8-bit pictures (compare.png's labels), drawn by OpenImageIO's
// FreeType renderer in DejaVu Sans Mono (Debian's fonts-dejavu-core, which
// scripts/setup.sh installs).

#include "jade/core/image.h"

#include <string>

namespace jade {

// Draws `text` with its left end at x and its baseline at y, `size` pixels
// high, clipped to the image. Returns false, having drawn nothing, when no
// font can be loaded: a picture is still worth writing without its labels.
bool draw_text(RgbImage8& image, int x, int baseline_y, const std::string& text, int size,
               const Rgb8& colour);

}  // namespace jade
