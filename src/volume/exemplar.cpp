#include "jade/volume/exemplar.h"

#include "jade/volume/noise.h"
#include "jade/volume/structure_estimate.h"
#include "jade/volume/texture_spectrum.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace jade {

namespace {

// One output sample's source pixels and weights, along one axis.
using Taps = std::vector<std::pair<int, double>>;

// Resampling `count` outputs from pixels starting at `first`, `step` pixels
// per output: where an output covers a pixel or more, the mean of what it
// covers (each pixel by the share of it covered); where it covers less, the
// linear interpolation of the two pixels around its centre.
std::vector<Taps> resampling_taps(int first, int count, double step) {
    std::vector<Taps> taps(static_cast<std::size_t>(count));
    const int last = first + int(std::ceil(count * step)) - 1;
    for (int i = 0; i < count; ++i) {
        Taps& t = taps[std::size_t(i)];
        if (step >= 1.0) {
            const double a = first + i * step, b = a + step;
            for (int p = int(std::floor(a)); p < int(std::ceil(b)); ++p) {
                const double w = std::min(b, p + 1.0) - std::max(a, double(p));
                if (w > 0.0) t.emplace_back(std::min(p, last), w / step);
            }
        } else {
            const double c = first + (i + 0.5) * step - 0.5;  // in pixel-centre coordinates
            const int p = int(std::floor(c));
            const double f = c - p;
            t.emplace_back(std::clamp(p, first, last), 1.0 - f);
            t.emplace_back(std::clamp(p + 1, first, last), f);
        }
    }
    return taps;
}

// i brought into [0, n): periodically, or mirrored (… 1 0 | 0 1 … n−1 | n−1 n−2 …).
int repeat(int i, int n, bool periodic) {
    if (periodic) return ((i % n) + n) % n;
    const int period = 2 * n;
    int j = ((i % period) + period) % period;
    return j < n ? j : period - 1 - j;
}

}  // namespace

float Exemplar::at(int x, int y) const {
    return values[std::size_t(repeat(y, side, periodic)) * side + std::size_t(repeat(x, side, periodic))];
}

bool tiles_seamlessly(const std::vector<float>& v, int n) {
    if (n < 2) return true;
    double inside = 0.0, seam = 0.0;
    for (int a = 0; a < n; ++a) {
        for (int b = 0; b + 1 < n; ++b) {
            const double along_row = v[std::size_t(a) * n + b + 1] - v[std::size_t(a) * n + b];
            const double along_column = v[std::size_t(b + 1) * n + a] - v[std::size_t(b) * n + a];
            inside += along_row * along_row + along_column * along_column;
        }
        const double across_x = v[std::size_t(a) * n] - v[std::size_t(a) * n + n - 1];
        const double across_y = v[std::size_t(a)] - v[std::size_t(n - 1) * n + a];
        seam += across_x * across_x + across_y * across_y;
    }
    return seam / (2.0 * n) <= 2.0 * inside / (2.0 * n * (n - 1));
}

Exemplar make_exemplar(const Photo& photo, int resolution) {
    const GrayImage luma = photo_luma(photo);
    const std::array<int, 3> square = largest_inside_square(luma);
    const double step = photo_pixels_per_side(photo) / resolution;  // photo pixels per voxel
    const int side = std::max(1, int(std::floor(square[2] / step)));
    const std::vector<Taps> along_x = resampling_taps(square[0], side, step);
    const std::vector<Taps> along_y = resampling_taps(square[1], side, step);
    Exemplar e;
    e.side = side;
    e.values.resize(std::size_t(side) * side);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            double acc = 0.0;
            for (const auto& [py, wy] : along_y[std::size_t(y)])
                for (const auto& [px, wx] : along_x[std::size_t(x)])
                    acc += wy * wx * luma.values[std::size_t(py) * luma.width + std::size_t(px)];
            e.values[std::size_t(y) * side + x] = float(acc);
        }
    e.periodic = tiles_seamlessly(e.values, side);
    return e;
}

std::array<int, 2> sweep_offset(int z, int resolution, std::uint32_t seed, double wander) {
    const SimplexNoise noise(seed);
    const double t = (z + 0.5) / resolution;  // cube sides
    std::array<int, 2> offset{0, 0};
    for (int axis = 0; axis < 2; ++axis) {
        // Three octaves from one cycle per side, amplitude ratio 1/2, each
        // axis on its own line through the lattice; over the amplitudes'
        // sum 1.75 so the wander is a bound.
        double value = 0.0, amplitude = 1.0, frequency = 1.0;
        for (int octave = 0; octave < 3; ++octave) {
            value += amplitude * noise(t * frequency + 17.3 * octave, 31.7 + 53.1 * axis, 7.9);
            amplitude *= 0.5, frequency *= 2.0;
        }
        offset[std::size_t(axis)] = int(std::lround(value / 1.75 * wander * resolution));
    }
    return offset;
}

void swept_slice(const Exemplar& e, int s, int z, std::uint32_t seed, double wander, float* out) {
    const std::array<int, 2> d = sweep_offset(z, s, seed, wander);
    for (int y = 0; y < s; ++y)
        for (int x = 0; x < s; ++x) out[std::size_t(y) * s + x] = e.at(x + d[0], s - 1 - y + d[1]);
}

}  // namespace jade
