#include "jade/volume/sharpen.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>

namespace jade {

namespace {

// The sampled Gaussian, normalised to sum 1, cut at three standard
// deviations: taps −h..h.
std::vector<float> gaussian_taps(double radius) {
    const int h = std::max(1, int(std::ceil(3.0 * radius)));
    std::vector<float> taps(std::size_t(2 * h + 1));
    double sum = 0.0;
    for (int i = -h; i <= h; ++i) sum += taps[std::size_t(i + h)] = float(std::exp(-0.5 * i * i / (radius * radius)));
    for (float& t : taps) t = float(t / sum);
    return taps;
}

// Blurs every line of `grid` (s³) along one axis in place: line (a, b)
// holds the voxels whose other two coordinates are a and b, `stride` apart.
void blur_axis(std::vector<float>& grid, int s, int axis, const std::vector<float>& taps) {
    const std::size_t stride = axis == 0 ? 1 : axis == 1 ? std::size_t(s) : std::size_t(s) * s;
    const int h = int(taps.size() / 2);
    tbb::parallel_for(tbb::blocked_range<int>(0, s * s, 64), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> line(static_cast<std::size_t>(s));
        for (int l = r.begin(); l < r.end(); ++l) {
            const int a = l % s, b = l / s;
            // The line's first voxel: the two coordinates that are not `axis`.
            const std::size_t first = axis == 0   ? (std::size_t(b) * s + a) * s
                                      : axis == 1 ? std::size_t(b) * s * s + a
                                                  : std::size_t(b) * s + a;
            for (int i = 0; i < s; ++i) line[std::size_t(i)] = grid[first + std::size_t(i) * stride];
            for (int i = 0; i < s; ++i) {
                float acc = 0.f;
                for (int t = -h; t <= h; ++t)
                    acc += taps[std::size_t(t + h)] * line[std::size_t(std::clamp(i + t, 0, s - 1))];
                grid[first + std::size_t(i) * stride] = acc;
            }
        }
    });
}

}  // namespace

std::array<double, 3> sharpen_levels(std::vector<Rgb8>& levels, int resolution, double amount, double radius) {
    std::array<double, 3> clipped{0.0, 0.0, 0.0};
    if (!(amount > 0.0) || levels.empty()) return clipped;
    const int s = resolution;
    const std::size_t n = levels.size();
    const std::vector<float> taps = gaussian_taps(radius);
    std::vector<float> blurred(n);
    for (int c = 0; c < 3; ++c) {
        for (std::size_t i = 0; i < n; ++i) blurred[i] = float(levels[i][std::size_t(c)]);
        for (int axis = 0; axis < 3; ++axis) blur_axis(blurred, s, axis, taps);
        std::atomic<std::size_t> clips{0};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<std::size_t>& r) {
            std::size_t local = 0;
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                const double v = levels[i][std::size_t(c)];
                const double sharp = v + amount * (v - double(blurred[i]));
                local += sharp < 0.0 || sharp > 255.0;
                levels[i][std::size_t(c)] = std::uint8_t(std::lround(std::clamp(sharp, 0.0, 255.0)));
            }
            clips += local;
        });
        clipped[std::size_t(c)] = double(clips) / double(n);
    }
    return clipped;
}

std::string sharpening_warning(double amount, const std::array<double, 3>& clipped) {
    if (*std::max_element(clipped.begin(), clipped.end()) <= kSharpenClipWarning) return "";
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "--sharpen %.3g clipped %.0f %%, %.0f %% and %.0f %% of the voxels (R, G, B) to level 0 or 255: "
                  "the clipped structure loses its levels; a smaller --sharpen keeps them",
                  amount, 100.0 * clipped[0], 100.0 * clipped[1], 100.0 * clipped[2]);
    return buf;
}

NoiseParams default_photo_noise() {
    NoiseParams noise;
    noise.sharpen = kDefaultSharpen;
    return noise;
}

}  // namespace jade
