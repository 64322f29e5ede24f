#include "jade/volume/texture_spectrum.h"

#include "jade/core/math.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>

namespace jade {

std::array<int, 3> largest_inside_square(const GrayImage& image) {
    // side(x, y): the largest square of texture pixels whose lower right
    // corner is (x, y); one row of it is kept at a time.
    const int w = image.width;
    std::vector<int> prev(std::size_t(w) + 1, 0), cur(std::size_t(w) + 1, 0);
    std::array<int, 3> best{0, 0, 0};
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < w; ++x) {
            cur[x + 1] = image.inside(x, y) ? 1 + std::min({prev[x], prev[x + 1], cur[x]}) : 0;
            if (cur[x + 1] > best[2]) best = {x - cur[x + 1] + 1, y - cur[x + 1] + 1, cur[x + 1]};
        }
        std::swap(prev, cur);
    }
    return best;
}

double TextureSpectrum::band_low(int b) { return std::exp2(0.5 * b); }

int TextureSpectrum::measured_bands() const {
    return int(std::count_if(power.begin(), power.end(), [](double p) { return p >= 0.0; }));
}

namespace {

// The periodogram of the square, Hann-windowed with its mean removed, less the
// white-noise floor; index (ky, kx) as the DFT leaves it. A bin may go
// negative: a bin's noise is exponentially distributed about the floor, so
// clamping each bin would leave a third of the noise in; sums over many bins
// average it out instead.
cv::Mat periodogram(const GrayImage& image, const std::array<int, 3>& sq, double noise_variance) {
    const int n = sq[2];
    cv::Mat values(n, n, CV_32F);
    double mean = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            mean += image.values[std::size_t(sq[1] + y) * image.width + sq[0] + x];
    mean /= double(n) * n;
    std::vector<double> hann(n);
    double window_energy = 0.0;  // Σ w², what white noise of variance 1 puts in every bin
    for (int i = 0; i < n; ++i) hann[i] = 0.5 - 0.5 * std::cos(2.0 * kPiD * (i + 0.5) / n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double w = hann[x] * hann[y];
            window_energy += w * w;
            values.at<float>(y, x) =
                float(w * (image.values[std::size_t(sq[1] + y) * image.width + sq[0] + x] - mean));
        }
    cv::Mat spectrum;
    cv::dft(values, spectrum, cv::DFT_COMPLEX_OUTPUT);
    cv::Mat power(n, n, CV_64F);
    const double floor = noise_variance * window_energy;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const cv::Vec2f c = spectrum.at<cv::Vec2f>(y, x);
            power.at<double>(y, x) = double(c[0]) * c[0] + double(c[1]) * c[1] - floor;
        }
    return power;
}

// The gradient structure tensor summed over blocks: Σ_blocks (λ1 − λ2) over
// Σ_blocks (λ1 + λ2), with central differences.
double local_coherence(const GrayImage& image, const std::array<int, 3>& sq, double pixels_per_side) {
    const int n = sq[2];
    const int block = std::max(4, int(std::lround(pixels_per_side / 32.0)));
    auto at = [&](int x, int y) { return double(image.values[std::size_t(sq[1] + y) * image.width + sq[0] + x]); };
    double anisotropic = 0.0, energy = 0.0;
    for (int by = 1; by + block <= n - 1; by += block)
        for (int bx = 1; bx + block <= n - 1; bx += block) {
            double jxx = 0.0, jxy = 0.0, jyy = 0.0;
            for (int y = by; y < by + block; ++y)
                for (int x = bx; x < bx + block; ++x) {
                    const double gx = 0.5 * (at(x + 1, y) - at(x - 1, y));
                    const double gy = 0.5 * (at(x, y + 1) - at(x, y - 1));
                    jxx += gx * gx, jxy += gx * gy, jyy += gy * gy;
                }
            anisotropic += std::sqrt((jxx - jyy) * (jxx - jyy) + 4.0 * jxy * jxy);
            energy += jxx + jyy;
        }
    return energy > 0.0 ? anisotropic / energy : 0.0;
}

}  // namespace

TextureSpectrum texture_spectrum(const GrayImage& image, double pixels_per_side, double noise_variance) {
    TextureSpectrum out;
    out.power.fill(-1.0);
    const std::array<int, 3> sq = largest_inside_square(image);
    const int n = sq[2];
    out.square = n;
    if (n < 8) return out;
    const cv::Mat power = periodogram(image, sq, noise_variance);
    out.coherence = local_coherence(image, sq, pixels_per_side);

    // Bands the square measures: at least two cycles across it, at most Nyquist.
    const double f_min = 2.0 * pixels_per_side / n, f_max = 0.5 * pixels_per_side;
    std::array<double, TextureSpectrum::kBands> sum{};
    std::array<bool, TextureSpectrum::kBands> measured{};
    for (int b = 0; b < TextureSpectrum::kBands; ++b)
        measured[b] = TextureSpectrum::band_low(b) >= f_min && TextureSpectrum::band_low(b + 1) <= f_max;
    double txx = 0.0, txy = 0.0, tyy = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const int kx = x <= n / 2 ? x : x - n, ky = y <= n / 2 ? y : y - n;
            if (kx == 0 && ky == 0) continue;
            const double radius = std::sqrt(double(kx) * kx + double(ky) * ky);
            const double f = radius / n * pixels_per_side;
            const int b = int(std::floor(2.0 * std::log2(f)));
            if (b < 0 || b >= TextureSpectrum::kBands || !measured[b]) continue;
            const double p = power.at<double>(y, x);
            sum[b] += p;
            // Orientation tensor of the frequency directions, y up as displayed.
            const double ux = kx / radius, uy = -ky / radius;
            txx += p * ux * ux;
            txy += p * ux * uy;
            tyy += p * uy * uy;
        }
    double total = 0.0;
    for (int b = 0; b < TextureSpectrum::kBands; ++b) total += std::max(0.0, sum[b]);
    if (!(total > 0.0)) return out;
    for (int b = 0; b < TextureSpectrum::kBands; ++b)
        if (measured[b]) out.power[b] = std::max(0.0, sum[b]) / total;
    // The dominant frequency direction is across the structure.
    const double across = 0.5 * std::atan2(2.0 * txy, txx - tyy);
    out.orientation = std::fmod(degrees(across) + 90.0 + 360.0, 180.0);
    out.strength = std::sqrt((txx - tyy) * (txx - tyy) + 4.0 * txy * txy) / (txx + tyy);
    return out;
}

double structure_distance(const TextureSpectrum& a, const TextureSpectrum& b) {
    double sa = 0.0, sb = 0.0;
    int common = 0;
    for (int i = 0; i < TextureSpectrum::kBands; ++i)
        if (a.power[i] >= 0.0 && b.power[i] >= 0.0) {
            sa += a.power[i];
            sb += b.power[i];
            ++common;
        }
    if (common < 2 || !(sa > 0.0) || !(sb > 0.0)) return -1.0;
    // A band with no power at all is held at a millionth of the total, so one
    // empty band costs a bounded amount rather than infinity.
    constexpr double kFloor = 1e-6;
    double sq = 0.0;
    for (int i = 0; i < TextureSpectrum::kBands; ++i)
        if (a.power[i] >= 0.0 && b.power[i] >= 0.0) {
            const double d = std::log10(std::max(a.power[i] / sa, kFloor)) -
                             std::log10(std::max(b.power[i] / sb, kFloor));
            sq += d * d;
        }
    return std::sqrt(sq / common);
}

double orientation_difference(double a, double b) {
    const double d = std::fmod(std::abs(a - b), 180.0);
    return std::min(d, 180.0 - d);
}

}  // namespace jade
