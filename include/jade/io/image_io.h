#pragma once
// Writing images through OpenImageIO, whole or not at all.

#include "jade/core/image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace jade {

// Writes 8-bit pixels (row-major, row 0 at the top, `channels` interleaved)
// in the format the file name's extension asks for.
void write_image_u8(const std::string& path, int width, int height, int channels,
                    const std::vector<std::uint8_t>& pixels);

// Writes float pixels (linear radiance) likewise; EXR keeps them as float.
// With 4 channels the alpha is taken as straight (unassociated) unless
// `associated_alpha` says the colour is already multiplied by it.
void write_image_f32(const std::string& path, int width, int height, int channels,
                     const std::vector<float>& pixels, bool associated_alpha = false);

// Reads any format OpenImageIO knows as float (its first kMaxImageChannels
// channels, at most kMaxImagePixels pixels: core/image.h). 8-bit files are decoded from
// sRGB to linear (an HDR/EXR is linear already). Throws jade::Error naming
// the file, also when the decoder reports any problem (a truncated file).
ImageF32 read_image_f32(const std::string& path);

// The image resampled to width x height (OpenImageIO's filtered resize).
ImageF32 resize_image(const ImageF32& image, int width, int height);

}  // namespace jade
