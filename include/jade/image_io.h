#pragma once
// Writing images through OpenImageIO, whole or not at all.

#include <cstdint>
#include <string>
#include <vector>

namespace jade {

// Writes 8-bit pixels (row-major, row 0 at the top, `channels` interleaved)
// in the format the file name's extension asks for.
void write_image_u8(const std::string& path, int width, int height, int channels,
                    const std::vector<std::uint8_t>& pixels);

// Writes float pixels (linear radiance) likewise; EXR keeps them as float.
void write_image_f32(const std::string& path, int width, int height, int channels,
                     const std::vector<float>& pixels);

}  // namespace jade
