#pragma once
// The input photograph: its colours as the sRGB-encoded 8-bit levels the
// method works in (paper §4.2, §5.1), and which pixels show the object.

#include "jade/core/image.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace jade {

struct Photo {
    int width = 0;
    int height = 0;
    std::vector<Rgb8> levels;             // row-major, row 0 at the top
    std::vector<std::uint8_t> foreground; // 1 where the pixel shows the object
    std::string path;
    // How many cube sides (the object's size) the foreground's larger side
    // spans: 1 when the photo is as wide as the object, 4 for a slab four
    // times as wide, of which the object shows a quarter, its structure four
    // times coarser than at 1 (docs/design.md, "The photo's span").
    double span = 1.0;

    std::size_t foreground_count() const;
    // The foreground pixels' colours, in row-major order.
    std::vector<Rgb8> foreground_levels() const;
    // The foreground's bounding box, {x0, y0, width, height} (the whole
    // image when there is no foreground).
    std::array<int, 4> foreground_box() const;
};

// Reads a photo (PNG, JPEG, TIFF, EXR, anything OpenImageIO reads; 8-bit,
// 16-bit or float; with or without alpha). Integer images are taken to be
// sRGB-encoded already; float images (EXR, float TIFF) are linear and are
// sRGB-encoded here. The foreground is alpha >= 0.5, or every pixel when there
// is no alpha; a mask image (same size, white = object, value >= 0.5 in its
// first channel) replaces the alpha when given. `span`: Photo::span. Throws
// jade::Error on an unreadable file, a mask of another size, a photo with no
// foreground, or a span out of range.
Photo load_photo(const std::string& path, const std::string& mask_path = "", double span = 1.0);

// The spans a photo may take: from a close-up an eighth of the object's size
// to a slab eight times as wide (the structure estimate's grids, scaled by
// the span, stay within NoiseParams::validate's ranges there).
constexpr double kMinPhotoSpan = 0.125;
constexpr double kMaxPhotoSpan = 8.0;
// Throws jade::Error naming `name` (the flag, or a file's metadata) when
// `span` is outside them.
void validate_photo_span(double span, const char* name = "--photo-span");
// " (spanning S cube sides)" for a summary line; "" at span 1.
std::string photo_span_note(double span);

}  // namespace jade
