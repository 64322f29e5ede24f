#include "jade/render/film.h"

#include "jade/core/error.h"
#include "jade/core/memory.h"

#include "jade/core/display.h"

#include <algorithm>

#include <cmath>
#include <cstring>
#include <cstdint>
#include <limits>

namespace jade {

namespace {
// Rousselle, Knaus & Zwicker 2011's guard against division by near-black pixels.
constexpr double kRelativeEpsilon = 0.01;
}

namespace {
// Fixed-point unit of the film's sums: 2^-64. A sample's value is clamped to
// ±2^62 (radiance beyond 4.6e18 is no image) so that 2^63 such sums still fit.
constexpr double kUnit = 18446744073709551616.0;  // 2^64
constexpr double kLargest = 4611686018427387904.0;  // 2^62

// v·2^64 rounded to the nearest integer (ties to even), exactly. From 2^52
// on every double is an integer, M·2^(E−52) with M its 53-bit significand
// and E its exponent: shifting M is the conversion, read from the bits (a
// double's conversion to __int128 is a libgcc call that cost 2 % of a
// render, and the two 64-bit halves it was later split into took scene A
// 5 % more CPU time than the shift: 10.9 against 10.4 s over four
// interleaved pairs of 256-spp renders, the same pixels). x ≤ 2^126, so the
// shift stays within 128 bits.
// Below 2^52, adding and taking away 2^52 rounds x to an integer in the
// default rounding mode (nearbyint's, without a libm call on the baseline
// x86-64 instruction set).
__int128 to_fixed(double v) {
    constexpr double kRound = 4503599627370496.0;  // 2^52
    const double x = std::abs(std::clamp(v, -kLargest, kLargest)) * kUnit;
    __int128 magnitude;
    if (x < kRound) {
        magnitude = __int128(std::uint64_t((x + kRound) - kRound));
    } else {
        std::uint64_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        constexpr std::uint64_t kHidden = std::uint64_t(1) << 52;
        const int shift = int(bits >> 52) - 1075;  // E − 52, E = biased exponent − 1023
        magnitude = __int128((bits & (kHidden - 1)) | kHidden) << shift;
    }
    return v < 0.0 ? -magnitude : magnitude;
}
}  // namespace

namespace {
// The strata and replicates besides number 0, whose sums and counts are
// kept apart (number 0's are what the others leave of the pixel's).
constexpr int kOtherStrata = Film::kStrata - 1;
constexpr int kOtherReplicates = Film::kReplicates - 1;
// A film's memory per pixel: Σx and Σx² per channel, the two counts, the
// other strata's and replicates' Σx and counts, and the float RGBA image
// written from it.
constexpr std::uint64_t kFilmBytesPerPixel = (2 + kOtherStrata + kOtherReplicates) * 3 * sizeof(__int128) +
                                             (2 + kOtherStrata + kOtherReplicates) * sizeof(std::uint32_t) +
                                             4 * sizeof(float);

// Pixel i's sums in channel c and counts per part of a partition of its
// samples into 1 + `others` parts whose parts 1 … are stored apart, part 0
// being what they leave of the pixel's `total` and `total_count`; returns
// how many parts hold samples.
int split_sums(std::size_t i, int c, int others, const std::vector<__int128>& other_sums,
               const std::vector<std::uint32_t>& other_counts, __int128 total, std::uint32_t total_count,
               double* sums, std::uint32_t* counts) {
    int filled = 0;
    for (int k = 0; k < others; ++k) {
        const __int128 fixed = other_sums[3 * (others * i + k) + c];
        counts[k + 1] = other_counts[others * i + k];
        sums[k + 1] = double(fixed) / kUnit;
        total -= fixed;
        total_count -= counts[k + 1];
        filled += counts[k + 1] > 0 ? 1 : 0;
    }
    counts[0] = total_count;
    sums[0] = double(total) / kUnit;
    return filled + (total_count > 0 ? 1 : 0);
}

// The checks of one partition's sums read back (Film::from_sums).
void check_parts(const std::vector<__int128>& sums, const std::vector<std::uint32_t>& counts,
                 const std::vector<std::uint32_t>& total, int others, const char* what) {
    const std::size_t n = total.size();
    if (sums.size() != 3 * std::size_t(others) * n || counts.size() != std::size_t(others) * n)
        throw Error(std::string("a film's ") + what + " do not match its size");
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t in_parts = 0;
        for (int k = 0; k < others; ++k) in_parts += counts[std::size_t(others) * i + k];
        if (in_parts > total[i]) throw Error(std::string("a film's pixel has more samples in its ") + what + " than in all");
    }
}

int checked_size(int width, int height) {
    if (width < 0 || height < 0) throw Error("internal: a film's size is negative");
    require_memory(Film::memory_bytes(width, height),
                   "a " + std::to_string(width) + " x " + std::to_string(height) + " render (--width, --height)");
    return width;
}
}  // namespace

Film::Film(int width, int height)
    : width_(checked_size(width, height)), height_(height), sum_(std::size_t(width) * height * 3, 0),
      sum_sq_(std::size_t(width) * height * 3, 0), count_(std::size_t(width) * height, 0),
      hits_(std::size_t(width) * height, 0), stratum_sum_(std::size_t(width) * height * 3 * kOtherStrata, 0),
      stratum_count_(std::size_t(width) * height * kOtherStrata, 0),
      replicate_sum_(std::size_t(width) * height * 3 * kOtherReplicates, 0),
      replicate_count_(std::size_t(width) * height * kOtherReplicates, 0) {}

Film::Sums Film::zero_sums(int width, int height) {
    Sums s;
    s.width = width;
    s.height = height;
    const std::size_t n = std::size_t(std::max(width, 0)) * std::size_t(std::max(height, 0));
    s.sum.assign(3 * n, 0);
    s.sum_sq.assign(3 * n, 0);
    s.count.assign(n, 0);
    s.hits.assign(n, 0);
    s.stratum_sum.assign(3 * kOtherStrata * n, 0);
    s.stratum_count.assign(kOtherStrata * n, 0);
    s.replicate_sum.assign(3 * kOtherReplicates * n, 0);
    s.replicate_count.assign(kOtherReplicates * n, 0);
    return s;
}

Film Film::from_sums(Sums s) {
    Film film(s.width, s.height);
    const std::size_t n = std::size_t(s.width) * s.height;
    if (s.sum.size() != 3 * n || s.sum_sq.size() != 3 * n || s.count.size() != n || s.hits.size() != n)
        throw Error("a film's sums do not match its size");
    for (std::size_t i = 0; i < n; ++i)
        if (s.hits[i] > s.count[i]) throw Error("a film's pixel has more object hits than samples");
    check_parts(s.stratum_sum, s.stratum_count, s.count, kOtherStrata, "strata");
    check_parts(s.replicate_sum, s.replicate_count, s.count, kOtherReplicates, "replicates");
    film.stratum_sum_ = std::move(s.stratum_sum);
    film.stratum_count_ = std::move(s.stratum_count);
    film.replicate_sum_ = std::move(s.replicate_sum);
    film.replicate_count_ = std::move(s.replicate_count);
    film.sum_ = std::move(s.sum);
    film.sum_sq_ = std::move(s.sum_sq);
    film.count_ = std::move(s.count);
    film.hits_ = std::move(s.hits);
    return film;
}

std::uint64_t Film::memory_bytes(int width, int height) {
    return kFilmBytesPerPixel * std::uint64_t(std::max(width, 0)) * std::uint64_t(std::max(height, 0));
}

int Film::spp() const {
    return count_.empty() ? 0 : int(*std::max_element(count_.begin(), count_.end()));
}

int Film::fewest_samples() const {
    return count_.empty() ? 0 : int(*std::min_element(count_.begin(), count_.end()));
}

double Film::mean_samples() const {
    if (count_.empty()) return 0.0;
    double total = 0.0;
    for (const auto n : count_) total += double(n);
    return total / double(count_.size());
}

void Film::add_sample(int x, int y, const Spectrum& radiance, bool hit_object, int stratum, int replicate) {
    if (stratum < 0 || stratum >= kStrata) throw Error("internal: a film sample's stratum is out of range");
    if (replicate < 0 || replicate >= kReplicates) throw Error("internal: a film sample's replicate is out of range");
    const std::size_t i = index(x, y);
    for (int c = 0; c < 3; ++c) {
        const double v = radiance[c];
        const __int128 fixed = to_fixed(v);
        sum_[3 * i + c] += fixed;
        sum_sq_[3 * i + c] += to_fixed(v * v);  // exact in double: v is a float
        if (stratum > 0) stratum_sum_[3 * (kOtherStrata * i + (stratum - 1)) + c] += fixed;
        if (replicate > 0) replicate_sum_[3 * (kOtherReplicates * i + (replicate - 1)) + c] += fixed;
    }
    if (stratum > 0) ++stratum_count_[kOtherStrata * i + (stratum - 1)];
    if (replicate > 0) ++replicate_count_[kOtherReplicates * i + (replicate - 1)];
    ++count_[i];
    hits_[i] += hit_object ? 1u : 0u;
}

void Film::add_samples(int x, int y, const Spectrum& radiance, const std::array<std::uint32_t, kStrata>& per_stratum,
                       int replicate) {
    if (replicate < 0 || replicate >= kReplicates) throw Error("internal: a film sample's replicate is out of range");
    const std::size_t i = index(x, y);
    std::uint32_t n = 0;
    for (const std::uint32_t k : per_stratum) n += k;
    if (n == 0) return;
    for (int c = 0; c < 3; ++c) {
        const double v = radiance[c];
        const __int128 fixed = to_fixed(v);
        sum_[3 * i + c] += __int128(n) * fixed;
        sum_sq_[3 * i + c] += __int128(n) * to_fixed(v * v);
        for (int s = 1; s < kStrata; ++s)
            stratum_sum_[3 * (kOtherStrata * i + (s - 1)) + c] += __int128(per_stratum[std::size_t(s)]) * fixed;
        if (replicate > 0) replicate_sum_[3 * (kOtherReplicates * i + (replicate - 1)) + c] += __int128(n) * fixed;
    }
    for (int s = 1; s < kStrata; ++s) stratum_count_[kOtherStrata * i + (s - 1)] += per_stratum[std::size_t(s)];
    if (replicate > 0) replicate_count_[kOtherReplicates * i + (replicate - 1)] += n;
    count_[i] += n;
}

void Film::merge(const Film& o) {
    if (o.width_ != width_ || o.height_ != height_)
        throw Error("internal: films of different sizes cannot be merged");
    for (std::size_t k = 0; k < sum_.size(); ++k) {
        sum_[k] += o.sum_[k];
        sum_sq_[k] += o.sum_sq_[k];
    }
    for (std::size_t i = 0; i < count_.size(); ++i) {
        count_[i] += o.count_[i];
        hits_[i] += o.hits_[i];
    }
    for (std::size_t k = 0; k < stratum_sum_.size(); ++k) stratum_sum_[k] += o.stratum_sum_[k];
    for (std::size_t k = 0; k < stratum_count_.size(); ++k) stratum_count_[k] += o.stratum_count_[k];
    for (std::size_t k = 0; k < replicate_sum_.size(); ++k) replicate_sum_[k] += o.replicate_sum_[k];
    for (std::size_t k = 0; k < replicate_count_.size(); ++k) replicate_count_[k] += o.replicate_count_[k];
}

double Film::sum(std::size_t i, int c) const { return double(sum_[3 * i + c]) / kUnit; }
double Film::sum_sq(std::size_t i, int c) const { return double(sum_sq_[3 * i + c]) / kUnit; }

Spectrum Film::mean(int x, int y) const {
    const std::size_t i = index(x, y);
    const double n = count_[i];
    if (n == 0) return Spectrum(0.f);
    return Spectrum(float(pixel_mean(i, 0)), float(pixel_mean(i, 1)), float(pixel_mean(i, 2)));
}

Spectrum Film::replicates_mean(int x, int y, int first, int count) const {
    if (first < 0 || count < 1 || first + count > kReplicates)
        throw Error("internal: a film's replicate range is out of range");
    const std::size_t i = index(x, y);
    Spectrum m(0.f);
    for (int c = 0; c < 3; ++c) {
        double sums[kReplicates];
        std::uint32_t counts[kReplicates];
        split_sums(i, c, kOtherReplicates, replicate_sum_, replicate_count_, sum_[3 * i + c], count_[i], sums, counts);
        double sum = 0.0;
        std::uint32_t n = 0;
        for (int r = first; r < first + count; ++r) {
            sum += sums[r];
            n += counts[r];
        }
        m[c] = n > 0 ? float(sum / n) : 0.f;
    }
    return m;
}

// Pixel i's sums and counts in channel c per stratum (stratum 0 is what
// the others leave), and how many strata hold samples.
int Film::strata(std::size_t i, int c, double* sums, std::uint32_t* counts) const {
    return split_sums(i, c, kOtherStrata, stratum_sum_, stratum_count_, sum_[3 * i + c], count_[i], sums, counts);
}

// With samples in every stratum, the strata being equally likely (each
// sample's hero is uniform), the average of the strata's means: the
// stratified estimate, whose error has no part from how many samples fell
// in each stratum (64 samples are 21, 21 and 22: Σx/n would weigh one
// stratum more, at random, and in a white furnace, whose heroes differ
// far more than their samples do, that spread is most of the error).
// Otherwise Σx/n, each sample being unbiased on its own.
double Film::pixel_mean(std::size_t i, int c) const {
    const double n = count_[i];
    if (n == 0) return 0.0;
    double sums[kStrata];
    std::uint32_t counts[kStrata];
    if (strata(i, c, sums, counts) < kStrata) return sum(i, c) / n;
    double m = 0.0;
    for (int h = 0; h < kStrata; ++h) m += sums[h] / counts[h];
    return m / kStrata;
}

// The variance of pixel_mean. Once every replicate holds a whole turn of
// the heroes, it is read from the spread between the replicates' means
// (replicate_variance): their first events come from one scrambled sequence
// each (render/pixel_sampler.h), so samples within a replicate are not
// independent and only the replicates are. Before, from the samples as if
// independent (sample_variance), which overstates the error of sequences.
double Film::mean_variance(std::size_t i, int c) const {
    if (count_[i] < 2) return std::numeric_limits<double>::quiet_NaN();
    double sums[kReplicates];
    std::uint32_t counts[kReplicates];
    split_sums(i, c, kOtherReplicates, replicate_sum_, replicate_count_, sum_[3 * i + c], count_[i], sums, counts);
    for (int r = 0; r < kReplicates; ++r)
        if (counts[r] < std::uint32_t(kStrata)) return sample_variance(i, c);
    // The replicates' means weigh as their shares of the samples (a pass
    // cut short leaves them unequal): the variance of Σx/n = Σ_r (n_r/n) Y_r
    // is estimated by R/(R − 1) Σ_r (n_r/n)² (Y_r − Σx/n)², as for the ratio
    // estimator of cluster sampling; for replicates of one size it is the
    // replicates' sample variance over R. Each replicate holds whole turns
    // but for the last, so its mean is the heroes' stratified mean to one
    // sample (an unequal last turn only widens the spread: the safe side).
    const double n = count_[i], all = sum(i, c) / n;
    double spread = 0.0;
    for (int r = 0; r < kReplicates; ++r) {
        const double share = counts[r] / n, d = sums[r] / counts[r] - all;
        spread += share * share * d * d;
    }
    return spread * kReplicates / (kReplicates - 1.0);
}

// For the stratified mean, (1/K²) Σ_h σ_h²/n_h, with σ² pooled within the
// strata: Σx² − Σ_h S_h²/n_h has expectation Σ_h (n_h − 1) σ_h², so over
// n − K it is unbiased when the strata are of one size (as the pixel's
// samples make them, to one sample). With a stratum of fewer than two
// samples there is nothing to pool in it: the sample variance over n, which
// also counts the spread between the strata, is the safe side; for Σx/n it
// is the estimate itself.
double Film::sample_variance(std::size_t i, int c) const {
    const double n = count_[i];
    const double all = sum(i, c);
    const double sample = std::max(0.0, (sum_sq(i, c) - all * all / n) / (n - 1.0)) / n;
    double sums[kStrata];
    std::uint32_t counts[kStrata];
    if (strata(i, c, sums, counts) < kStrata) return sample;
    double between = 0.0, inverse_counts = 0.0;
    for (int h = 0; h < kStrata; ++h) {
        if (counts[h] < 2) return sample;
        between += sums[h] * sums[h] / counts[h];
        inverse_counts += 1.0 / counts[h];
    }
    const double pooled = std::max(0.0, sum_sq(i, c) - between) / (n - kStrata);
    return pooled * inverse_counts / (double(kStrata) * kStrata);
}

Spectrum Film::variance_of_mean(int x, int y) const {
    const std::size_t i = index(x, y);
    Spectrum v;
    for (int c = 0; c < 3; ++c) v[c] = float(mean_variance(i, c));
    return v;
}

float Film::coverage(int x, int y) const {
    const std::size_t i = index(x, y);
    if (count_[i] == 0) return 0.f;
    return float(hits_[i]) / float(count_[i]);
}

template <class Object, class Mean, class Variance>
double Film::relative_error(std::size_t pixels, Object object, Mean mean, Variance variance) {
    // The object's mean value sets the scale of the regulariser, so that the
    // measure does not depend on the image's exposure.
    double level = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
        if (!object(i)) continue;
        for (int c = 0; c < 3; ++c) level += mean(i, c);
        count += 3;
    }
    if (count == 0) return std::numeric_limits<double>::quiet_NaN();
    level /= double(count);
    const double epsilon = kRelativeEpsilon * std::max(level * level, 1e-30);
    double total = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) {
        if (!object(i)) continue;
        for (int c = 0; c < 3; ++c) {
            const double m = mean(i, c);
            total += variance(i, c) / (m * m + epsilon);
        }
    }
    return std::sqrt(total / double(count));
}

double Film::estimated_relative_error() const {
    return relative_error(
        count_.size(),
        [&](std::size_t i) { return count_[i] >= 2 && is_object_pixel(float(hits_[i]) / float(count_[i])); },
        [&](std::size_t i, int c) { return pixel_mean(i, c); },
        [&](std::size_t i, int c) { return mean_variance(i, c); });
}

double Film::relative_error_across(const std::vector<Film>& groups) {
    const std::size_t k = groups.size();
    if (k < 2) throw Error("internal: an error across groups needs at least two of them");
    const std::size_t pixels = groups[0].count_.size();
    for (const Film& g : groups)
        if (g.width_ != groups[0].width_ || g.height_ != groups[0].height_)
            throw Error("internal: groups of different sizes");
    for (std::size_t i = 0; i < pixels; ++i)
        for (const Film& g : groups)
            if (g.count_[i] == 0 || g.count_[i] != groups[0].count_[i])
                throw Error("internal: the groups must hold equally many samples in every pixel");
    const auto object = [&](std::size_t i) {
        std::uint64_t hits = 0, count = 0;
        for (const Film& g : groups) hits += g.hits_[i], count += g.count_[i];
        return is_object_pixel(float(double(hits) / double(count)));
    };
    const auto mean = [&](std::size_t i, int c) {
        double m = 0.0;
        for (const Film& g : groups) m += g.pixel_mean(i, c);
        return m / double(k);
    };
    const auto variance = [&](std::size_t i, int c) {
        const double m = mean(i, c);
        double v = 0.0;
        for (const Film& g : groups) {
            const double d = g.pixel_mean(i, c) - m;
            v += d * d;
        }
        return v / double(k - 1);
    };
    return relative_error(pixels, object, mean, variance);
}

std::vector<float> Film::rgba(bool alpha_is_coverage) const {
    std::vector<float> out(std::size_t(width_) * height_ * 4);
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const std::size_t i = std::size_t(y) * width_ + x;
            const Spectrum m = mean(x, y);
            out[4 * i] = m.x;
            out[4 * i + 1] = m.y;
            out[4 * i + 2] = m.z;
            out[4 * i + 3] = alpha_is_coverage ? coverage(x, y) : 1.f;
        }
    return out;
}

Film box_downsampled(const Film& film, int factor) {
    if (factor < 1 || film.width() % factor != 0 || film.height() % factor != 0)
        throw Error("internal: a film of " + std::to_string(film.width()) + "x" + std::to_string(film.height()) +
                    " cannot be box-downsampled by " + std::to_string(factor));
    Film::Sums s = Film::zero_sums(film.width() / factor, film.height() / factor);
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const std::size_t i = std::size_t(y) * film.width() + x;
            const std::size_t o = std::size_t(y / factor) * s.width + x / factor;
            for (int c = 0; c < 3; ++c) {
                s.sum[3 * o + c] += film.sums()[3 * i + c];
                s.sum_sq[3 * o + c] += film.sums_of_squares()[3 * i + c];
            }
            s.count[o] += film.counts()[i];
            s.hits[o] += film.object_hits()[i];
            for (int k = 0; k < 3 * kOtherStrata; ++k)
                s.stratum_sum[3 * kOtherStrata * o + k] += film.stratum_sums()[3 * kOtherStrata * i + k];
            for (int k = 0; k < kOtherStrata; ++k)
                s.stratum_count[kOtherStrata * o + k] += film.stratum_counts()[kOtherStrata * i + k];
            for (int k = 0; k < 3 * kOtherReplicates; ++k)
                s.replicate_sum[3 * kOtherReplicates * o + k] += film.replicate_sums()[3 * kOtherReplicates * i + k];
            for (int k = 0; k < kOtherReplicates; ++k)
                s.replicate_count[kOtherReplicates * o + k] += film.replicate_counts()[kOtherReplicates * i + k];
        }
    return Film::from_sums(std::move(s));
}

ReferenceError compare_with_reference(const Film& film, const ImageF32& ref) {
    if (ref.width != film.width() || ref.height != film.height() || ref.channels < 3)
        throw Error("the reference image is " + std::to_string(ref.width) + "x" +
                    std::to_string(ref.height) + " with " + std::to_string(ref.channels) +
                    " channels; the render is " + std::to_string(film.width()) + "x" +
                    std::to_string(film.height()) + " RGB");
    double se = 0.0, rel = 0.0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const Spectrum m = film.mean(x, y);
            for (int c = 0; c < 3; ++c) {
                const double r = ref.at(x, y, c), e = double(m[c]) - r;
                se += e * e;
                rel += e * e / (r * r + kRelativeEpsilon);
            }
        }
    const double n = 3.0 * film.width() * film.height();
    return {std::sqrt(se / n), rel / n};
}

}  // namespace jade

namespace jade {

void write_film(const Film& film, const std::string& exr_path, const std::string& png_path,
                bool alpha_is_coverage, float png_exposure) {
    const std::vector<float> rgba = film.rgba(alpha_is_coverage);
    std::vector<std::uint8_t> png;
    if (!png_path.empty()) {
        png.resize(rgba.size());
        for (std::size_t i = 0; i < rgba.size(); i += 4) {
            const float a = rgba[i + 3];
            for (int c = 0; c < 3; ++c) {
                // With coverage alpha the film holds colour × coverage; PNG wants it straight.
                const float straight =
                    png_exposure * (alpha_is_coverage && a > 0.f ? rgba[i + c] / a : rgba[i + c]);
                png[i + c] = display_level(straight);
            }
            png[i + 3] = std::uint8_t(std::lround(255.f * std::clamp(a, 0.f, 1.f)));
        }
    }
    write_image_f32(exr_path, film.width(), film.height(), 4, rgba, /*associated_alpha=*/true);
    if (!png_path.empty()) write_image_u8(png_path, film.width(), film.height(), 4, png);
}

}  // namespace jade
