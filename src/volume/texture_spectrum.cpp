#include "jade/volume/texture_spectrum.h"

#include "jade/core/error.h"
#include "jade/core/math.h"
#include "jade/core/random.h"

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

int TextureSpectrum::bands_below_noise() const {
    int n = 0;
    for (int b = 0; b < kBands; ++b) n += power[b] >= 0.0 && below_noise[b];
    return n;
}

namespace {

// The square's values, Hann-windowed with their mean removed, and their DFT.
struct WindowedDft {
    cv::Mat spectrum;            // complex, index (ky, kx) as the DFT leaves it
    double window_energy = 0.0;  // Σ w², what white noise of variance 1 puts in every bin
};
WindowedDft windowed_dft(const GrayImage& image, const std::array<int, 3>& sq) {
    const int n = sq[2];
    auto at = [&](int x, int y) { return double(image.values[std::size_t(sq[1] + y) * image.width + sq[0] + x]); };
    double mean = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) mean += at(x, y);
    mean /= double(n) * n;
    std::vector<double> hann(n);
    for (int i = 0; i < n; ++i) hann[i] = 0.5 - 0.5 * std::cos(2.0 * kPiD * (i + 0.5) / n);
    WindowedDft out;
    cv::Mat values(n, n, CV_32F);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double w = hann[x] * hann[y];
            out.window_energy += w * w;
            values.at<float>(y, x) = float(w * (at(x, y) - mean));
        }
    cv::dft(values, out.spectrum, cv::DFT_COMPLEX_OUTPUT);
    return out;
}

// A (cross-)periodogram of one square, and the power per bin of the images'
// noise: a render's pixels carry independent noise, white, the same in
// every bin however its strength varies over the image.
struct Periodogram {
    cv::Mat power;             // CV_64F, index (ky, kx) as the DFT leaves it
    double noise_power = 0.0;  // 0 for images without noise
    // A bin's variance under noise alone over the square of its noise power:
    // |N|² − σ² of one image varies by σ⁴; Re(N_a·conj(N_b)) of two, by σ⁴/2.
    double noise_variance_ratio = 1.0;
};

// The cross-periodogram Re(A·conj(B)) of two images over one square, less
// the white-noise floor; A = B gives the periodogram. Noise that the two
// images do not share averages out of it. A bin may go negative: a bin's
// noise is exponentially distributed about the floor, so clamping each bin
// would leave a third of the noise in; sums over many bins average it out
// instead. The noise's power is the floor, or of two images (A = S + N_a,
// B = S + N_b, the noises independent and alike) half of |A − B|² =
// |N_a − N_b|² over all bins, which the structure they share leaves out.
Periodogram cross_periodogram(const GrayImage& a, const GrayImage& b, const std::array<int, 3>& sq,
                              double noise_variance) {
    const int n = sq[2];
    const WindowedDft fa = windowed_dft(a, sq);
    const bool two = &a != &b;
    const WindowedDft fb = two ? windowed_dft(b, sq) : fa;
    Periodogram out{cv::Mat(n, n, CV_64F), 0.0, two ? 0.5 : 1.0};
    const double floor = noise_variance * fa.window_energy;
    double difference = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const cv::Vec2f ca = fa.spectrum.at<cv::Vec2f>(y, x), cb = fb.spectrum.at<cv::Vec2f>(y, x);
            out.power.at<double>(y, x) = double(ca[0]) * cb[0] + double(ca[1]) * cb[1] - floor;
            const double dr = double(ca[0]) - cb[0], di = double(ca[1]) - cb[1];
            difference += dr * dr + di * di;
        }
    out.noise_power = floor + 0.5 * difference / (double(n) * n - 1.0);  // the DC bin is 0: means removed
    return out;
}

// What the bins' correlations make of a band's summed noise variance. A real
// image's DFT holds every bin twice (k and −k), and the Hann window couples
// each bin to its neighbours: with correlation 2/3 one bin apart and 1/6 two
// apart along each axis, a product of two bins' values (of one image or of
// two) correlates by their squares, (1 + 2·(2/3)² + 2·(1/6)²)² = (35/18)² in
// two dimensions.
constexpr double kBinCorrelation = 2.0 * (35.0 / 18.0) * (35.0 / 18.0);

struct Tensor {
    double xx = 0.0, xy = 0.0, yy = 0.0;
};

// TextureSpectrum::defects of a grid of blocks' tensors. The orientation is
// the tensor's doubled angle, so that a loop's turns count modulo a whole
// turn of the orientation; half a turn of it is a whole turn of the doubled
// angle. A block without one (flat, or isotropic exactly: λ1 = λ2) leaves
// the cells it bounds out of the count and of the share.
double orientation_defects(const std::vector<Tensor>& grid, int blocks) {
    std::vector<double> doubled(grid.size());
    std::vector<bool> oriented(grid.size());
    for (std::size_t i = 0; i < grid.size(); ++i) {
        const Tensor& t = grid[i];
        oriented[i] = (t.xx - t.yy) != 0.0 || t.xy != 0.0;
        doubled[i] = std::atan2(2.0 * t.xy, t.xx - t.yy);
    }
    auto turn = [](double d) { return std::remainder(d, 2.0 * kPiD); };
    int defects = 0, cells = 0;
    for (int j = 0; j + 1 < blocks; ++j)
        for (int i = 0; i + 1 < blocks; ++i) {
            const std::size_t loop[4] = {std::size_t(j) * blocks + i, std::size_t(j) * blocks + i + 1,
                                         std::size_t(j + 1) * blocks + i + 1, std::size_t(j + 1) * blocks + i};
            if (!(oriented[loop[0]] && oriented[loop[1]] && oriented[loop[2]] && oriented[loop[3]])) continue;
            double total = 0.0;
            for (int k = 0; k < 4; ++k) total += turn(doubled[loop[(k + 1) % 4]] - doubled[loop[k]]);
            ++cells;
            if (std::abs(total) > kPiD) ++defects;  // ±2π, or ±4π where two meet
        }
    return cells > 0 ? double(defects) / cells : 0.0;
}

// The gradient structure tensor summed over blocks a 32nd of a side wide,
// with central differences; of two images, the tensor of their gradients'
// products (∇a ∇bᵀ, symmetrised): what their noise does not share averages
// out of each block's tensor, though not wholly out of its eigenvalues'
// difference (a square root per block), nor out of its angle.
struct OrientationField {
    double coherence = 0.0;  // Σ_blocks (λ1 − λ2) over Σ_blocks (λ1 + λ2)
    double defects = 0.0;
};
OrientationField orientation_field(const GrayImage& a, const GrayImage& b, const std::array<int, 3>& sq,
                                   double pixels_per_side) {
    const int n = sq[2];
    const int block = std::max(4, int(std::lround(pixels_per_side / 32.0)));
    auto at = [&](const GrayImage& image, int x, int y) {
        return double(image.values[std::size_t(sq[1] + y) * image.width + sq[0] + x]);
    };
    auto gradient = [&](const GrayImage& image, int x, int y) {
        return std::array<double, 2>{0.5 * (at(image, x + 1, y) - at(image, x - 1, y)),
                                     0.5 * (at(image, x, y + 1) - at(image, x, y - 1))};
    };
    const int blocks = std::max(0, (n - 2) / block);  // per side; the first and last pixel have no gradient
    std::vector<Tensor> grid(std::size_t(blocks) * blocks);
    double anisotropic = 0.0, energy = 0.0;
    for (int j = 0; j < blocks; ++j)
        for (int i = 0; i < blocks; ++i) {
            Tensor& t = grid[std::size_t(j) * blocks + i];
            for (int y = 1 + j * block; y < 1 + (j + 1) * block; ++y)
                for (int x = 1 + i * block; x < 1 + (i + 1) * block; ++x) {
                    const auto ga = gradient(a, x, y), gb = gradient(b, x, y);
                    t.xx += ga[0] * gb[0], t.yy += ga[1] * gb[1];
                    t.xy += 0.5 * (ga[0] * gb[1] + ga[1] * gb[0]);
                }
            anisotropic += std::sqrt((t.xx - t.yy) * (t.xx - t.yy) + 4.0 * t.xy * t.xy);
            energy += t.xx + t.yy;
        }
    return {energy > 0.0 ? std::min(1.0, anisotropic / energy) : 0.0, orientation_defects(grid, blocks)};
}

// A spectrum of no measured band, of a square of side n.
TextureSpectrum unmeasured(int n) {
    TextureSpectrum out;
    out.power.fill(-1.0);
    out.square = n;
    return out;
}

// The bands, orientation and strength of a (cross-)periodogram of an n × n
// square. A band whose power is under TextureSpectrum::kDetection standard
// errors of the noise's is below_noise.
TextureSpectrum bands_of(const Periodogram& periodogram, int n, double pixels_per_side) {
    const cv::Mat& power = periodogram.power;
    TextureSpectrum out = unmeasured(n);
    // Bands the square measures: at least two cycles across it, at most Nyquist.
    const double f_min = 2.0 * pixels_per_side / n, f_max = 0.5 * pixels_per_side;
    std::array<double, TextureSpectrum::kBands> sum{};
    std::array<int, TextureSpectrum::kBands> bins{};
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
            ++bins[b];
            // Orientation tensor of the frequency directions, y up as displayed.
            const double ux = kx / radius, uy = -ky / radius;
            txx += p * ux * ux;
            txy += p * ux * uy;
            tyy += p * uy * uy;
        }
    double total = 0.0;
    for (int b = 0; b < TextureSpectrum::kBands; ++b) total += std::max(0.0, sum[b]);
    if (!(total > 0.0)) return out;
    for (int b = 0; b < TextureSpectrum::kBands; ++b) {
        if (!measured[b]) continue;
        const double error =
            std::sqrt(kBinCorrelation * periodogram.noise_variance_ratio * bins[b]) * periodogram.noise_power;
        out.power[b] = std::max(0.0, sum[b]) / total;
        out.error[b] = error / total;
        out.below_noise[b] = error > 0.0 && sum[b] < TextureSpectrum::kDetection * error;
    }
    // The dominant frequency direction is across the structure.
    const double across = 0.5 * std::atan2(2.0 * txy, txx - tyy);
    out.orientation = std::fmod(degrees(across) + 90.0 + 360.0, 180.0);
    // A cross-periodogram's tensor may come out of its range on noise alone.
    const double anisotropic = std::sqrt((txx - tyy) * (txx - tyy) + 4.0 * txy * txy);
    out.strength = txx + tyy > 0.0 ? std::min(1.0, anisotropic / (txx + tyy)) : 0.0;
    return out;
}

}  // namespace

TextureSpectrum texture_spectrum(const GrayImage& image, double pixels_per_side, double noise_variance) {
    const std::array<int, 3> sq = largest_inside_square(image);
    if (sq[2] < 8) return unmeasured(sq[2]);
    TextureSpectrum out = bands_of(cross_periodogram(image, image, sq, noise_variance), sq[2], pixels_per_side);
    const OrientationField field = orientation_field(image, image, sq, pixels_per_side);
    out.coherence = field.coherence, out.defects = field.defects;
    return out;
}

TextureSpectrum texture_cross_spectrum(const GrayImage& a, const GrayImage& b, double pixels_per_side) {
    if (a.width != b.width || a.height != b.height)
        throw Error("internal: texture_cross_spectrum needs two images of one size");
    GrayImage both = a;  // the pixels inside both images, for the square
    both.mask.assign(std::size_t(a.width) * a.height, 1);
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) both.mask[std::size_t(y) * a.width + x] = a.inside(x, y) && b.inside(x, y);
    const std::array<int, 3> sq = largest_inside_square(both);
    if (sq[2] < 8) return unmeasured(sq[2]);
    TextureSpectrum out = bands_of(cross_periodogram(a, b, sq, 0.0), sq[2], pixels_per_side);
    const OrientationField field = orientation_field(a, b, sq, pixels_per_side);
    out.coherence = field.coherence, out.defects = field.defects;
    return out;
}

namespace {

using Shares = std::array<double, TextureSpectrum::kBands>;

// structure_distance over two arrays of band shares (< 0: not measured).
double distance_of_shares(const Shares& a, const Shares& b) {
    double sa = 0.0, sb = 0.0;
    int common = 0;
    for (int i = 0; i < TextureSpectrum::kBands; ++i)
        if (a[i] >= 0.0 && b[i] >= 0.0) {
            sa += a[i];
            sb += b[i];
            ++common;
        }
    if (common < 2 || !(sa > 0.0) || !(sb > 0.0)) return -1.0;
    // A band with no power at all is held at a millionth of the total, so one
    // empty band costs a bounded amount rather than infinity.
    constexpr double kFloor = 1e-6;
    double sq = 0.0;
    for (int i = 0; i < TextureSpectrum::kBands; ++i)
        if (a[i] >= 0.0 && b[i] >= 0.0) {
            const double d = std::log10(std::max(a[i] / sa, kFloor)) - std::log10(std::max(b[i] / sb, kFloor));
            sq += d * d;
        }
    return std::sqrt(sq / common);
}

// One draw of a spectrum's shares: each measured band moved by its standard
// error times a standard normal (Box–Muller), and held at 0 from below as a
// measured band is.
Shares redrawn(const TextureSpectrum& s, SplitMix64& rng) {
    Shares out = s.power;
    for (int b = 0; b < TextureSpectrum::kBands; ++b) {
        if (s.power[b] < 0.0 || !(s.error[b] > 0.0)) continue;
        const double u1 = 1.0 - rng.uniform(), u2 = rng.uniform();
        const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPiD * u2);
        out[b] = std::max(0.0, s.power[b] + s.error[b] * z);
    }
    return out;
}

}  // namespace

double structure_distance(const TextureSpectrum& a, const TextureSpectrum& b) {
    return distance_of_shares(a.power, b.power);
}

double structure_distance_error(const TextureSpectrum& a, const TextureSpectrum& b) {
    if (distance_of_shares(a.power, b.power) < 0.0) return 0.0;
    // A fixed stream: the same spectra always state the same error.
    SplitMix64 rng(0x5EC7'5A11'D157'A4CEull);
    double sum = 0.0, sum_sq = 0.0;
    int n = 0;
    for (int i = 0; i < kStructureErrorDraws; ++i) {
        const double d = distance_of_shares(redrawn(a, rng), redrawn(b, rng));
        if (d < 0.0) continue;  // every band of a draw at 0: no distance to take
        sum += d;
        sum_sq += d * d;
        ++n;
    }
    if (n < 2) return 0.0;
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, (sum_sq - n * mean * mean) / (n - 1)));
}

TextureSpectrum common_bands(const TextureSpectrum& s, const TextureSpectrum& other) {
    TextureSpectrum out = s;
    for (int b = 0; b < TextureSpectrum::kBands; ++b)
        if (other.power[b] < 0.0) out.power[b] = -1.0;
    return out;
}

double orientation_difference(double a, double b) {
    const double d = std::fmod(std::abs(a - b), 180.0);
    return std::min(d, 180.0 - d);
}

}  // namespace jade
