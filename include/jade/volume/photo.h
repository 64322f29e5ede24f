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

    std::size_t foreground_count() const;
    // The foreground pixels' colours, in row-major order.
    std::vector<Rgb8> foreground_levels() const;
};

// Reads a photo (PNG, JPEG, TIFF, EXR, anything OpenImageIO reads; 8-bit,
// 16-bit or float; with or without alpha). Integer images are taken to be
// sRGB-encoded already; float images (EXR, float TIFF) are linear and are
// sRGB-encoded here. The foreground is alpha >= 0.5, or every pixel when there
// is no alpha; a mask image (same size, white = object, value >= 0.5 in its
// first channel) replaces the alpha when given. Throws jade::Error on an
// unreadable file, a mask of another size, or a photo with no foreground.
Photo load_photo(const std::string& path, const std::string& mask_path = "");

}  // namespace jade
