#pragma once
// Multi-part OpenEXR files of our own making: each part a rectangle of a
// larger image (its data window) with named channels, all float or all
// 32-bit unsigned integers, and string attributes. A split render's pieces
// are stored this way (app/render_piece.h): exact integer sums that no
// viewer needs, beside a float preview that any EXR viewer shows.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace jade {

struct ExrPart {
    std::string name;
    int full_width = 0, full_height = 0;   // the whole image (display window)
    int x0 = 0, y0 = 0, width = 0, height = 0;  // the rectangle stored (data window)
    std::vector<std::string> channels;
    bool integer = false;                  // UINT channels (else FLOAT)
    std::vector<float> floats;             // width * height * channels, interleaved
    std::vector<std::uint32_t> uints;      // likewise, for integer parts
    std::vector<std::pair<std::string, std::string>> attributes;

    // The value of attribute `key`, "" when it has none.
    std::string attribute(const std::string& key) const;
    // Index of channel `name` among `channels`, -1 when there is none.
    int channel(const std::string& name) const;
};

// Writes the parts into one file, whole or not at all (io/atomic_file.h).
void write_exr_parts(const std::string& path, const std::vector<ExrPart>& parts);

// Reads every part (at most `max_parts`). Each part's size is checked
// against kMaxImagePixels (core/image.h) and its channel count against
// `max_channels` before anything is allocated. Throws jade::Error naming the
// file on any problem, including a decoder's message.
std::vector<ExrPart> read_exr_parts(const std::string& path, int max_parts, int max_channels);

}  // namespace jade
