#pragma once
// Plain images, shared by every layer that reads, makes or writes pixels.

#include <array>
#include <cstdint>
#include <vector>

namespace jade {

// The largest image any reader accepts: 16384² pixels (1 GiB per float
// channel), checked against the file's header before anything is allocated,
// so a corrupt or lying header never asks for gigabytes; and the channels
// read (RGBA: further channels are not ours).
constexpr std::int64_t kMaxImagePixels = 16384LL * 16384LL;
constexpr int kMaxImageChannels = 4;

// One pixel's sRGB-encoded 8-bit levels (paper §4.2, §5.1: the method's colours).
using Rgb8 = std::array<std::uint8_t, 3>;

// A float image: linear values, row 0 at the top, channels interleaved.
struct ImageF32 {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;
    float at(int x, int y, int c) const {
        return pixels[(std::size_t(y) * width + x) * channels + c];
    }
};

// An 8-bit RGB image, row 0 at the top.
struct RgbImage8 {
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels;
    // Sets pixel (x, y); nothing outside the image (drawing may run over its edges).
    void put(int x, int y, const Rgb8& c) {
        if (x < 0 || y < 0 || x >= width || y >= height) return;
        std::uint8_t* p = &pixels[(std::size_t(y) * width + x) * 3];
        p[0] = c[0];
        p[1] = c[1];
        p[2] = c[2];
    }
};

}  // namespace jade
