#pragma once
// The film: per-pixel sums of the camera samples' radiance and of its square,
// so every pass knows the variance of each pixel's mean and can say how far
// the image is from converged without a reference. Pixels use a box filter
// (a pixel is the mean radiance over its square), as the reference renders do.
// A sample belongs to one of kStrata strata (its hero channel: a pixel's
// samples take them in turn, render/pixel_sampler.h), and each stratum's sum
// is kept too: the spread between the strata's means is not noise of the
// pixel's mean, so the variance is taken within strata (docs/design.md,
// "Stratified pixel samples"). A sample also belongs to one of kReplicates
// replicates (render/pixel_sampler.h), whose sums are kept too: once each
// holds samples, the variance is taken from the spread between their means,
// the samples within one replicate not being independent.

#include "jade/io/image_io.h"
#include "jade/core/spectrum.h"
#include "jade/render/pixel_sampler.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace jade {

class Film {
public:
    Film() : Film(0, 0) {}
    // Throws jade::Error (naming --width, --height) when a film of this size
    // would not fit in the memory available (core/memory.h).
    Film(int width, int height);
    // The memory a film of this size takes, with the image written from it.
    static std::uint64_t memory_bytes(int width, int height);
    int width() const { return width_; }
    int height() const { return height_; }
    // The most samples any pixel holds (a uniform render's samples per pixel).
    int spp() const;
    int samples(int x, int y) const { return int(count_[index(x, y)]); }
    // The smallest sample count of any pixel (after a pass cut short by a
    // time budget, pixels differ).
    int fewest_samples() const;
    // The samples per pixel on average: the render's whole work, above the
    // fewest when a pass was cut short.
    double mean_samples() const;

    static constexpr int kStrata = 3;
    static constexpr int kReplicates = jade::kReplicates;
    // Adds one sample of stratum `stratum` (0 ≤ stratum < kStrata) and
    // replicate `replicate` (0 ≤ replicate < kReplicates) to pixel (x, y).
    // A pixel is written by one thread at a time.
    void add_sample(int x, int y, const Spectrum& radiance, bool hit_object, int stratum = 0, int replicate = 0);
    // Adds per_stratum[s] samples of one value that misses the object to
    // stratum s and replicate `replicate` of pixel (x, y): the same sums, bit
    // for bit, as that many add_sample calls.
    void add_samples(int x, int y, const Spectrum& radiance, const std::array<std::uint32_t, kStrata>& per_stratum,
                     int replicate);
    // Adds another film's samples (same size), pixel by pixel. The sums are
    // exact, so merging is associative: pieces of a render merged in any
    // grouping give the bits of one render of all their samples.
    void merge(const Film& other);

    // The pixel's mean: with samples in every stratum the average of the
    // strata's means (the strata are equally likely), else Σx / n.
    // Variance of that mean, per channel: once every replicate holds kStrata
    // samples, from the spread between the replicates' means; before, from
    // the variance within strata, pooled (the sample variance over n when
    // not every stratum holds two samples: then the larger value). NaN
    // below 2 samples.
    Spectrum mean(int x, int y) const;
    Spectrum variance_of_mean(int x, int y) const;
    // Σx / n over the samples of replicates first … first + count − 1 of
    // pixel (x, y) (0 where they hold none). Two disjoint sets of replicates
    // are independent estimates of the pixel, each hero-balanced up to one
    // turn (render/pixel_sampler.h): what the images of both share is the
    // converged image, their noise apart.
    Spectrum replicates_mean(int x, int y, int first, int count) const;
    // Fraction of the pixel's camera rays that met the object.
    float coverage(int x, int y) const;

    // Estimated relative error of the image without a reference: the root of
    // the mean over the object's pixels (core/display.h) and channels of
    // Var[mean] / (mean² + 0.01 m̄²), m̄ the mean of those pixels — the
    // relative MSE of Rousselle et al. 2011 for the image scaled to mean 1:
    // its 0.01 keeps near-black pixels from dominating, and scaling makes the
    // measure independent of exposure (a render 10x darker is not 10x more
    // exact). NaN before 2 spp or when no pixel shows the object.
    // It reads low at few samples where rare bright samples carry much of
    // the variance: such a sample raises the pixel's mean with its variance,
    // so the pixel that caught one divides by an inflated mean² (on the
    // demo's final render 16 % low at 32 spp, 10 % at 64, 5 % at 128 and
    // exact at 256; README, "Output, and error against run time").
    double estimated_relative_error() const;
    // The same measure taken across `groups`, films of one size that hold
    // equally many independent samples each (sample ranges of one render):
    // for the error of one group's mean, per object pixel the groups' means'
    // sample variance over (m² + 0.01 m̄²), m the pixel's mean over all the
    // groups. Each group's variance is then measured from outside it and
    // divided by a mean of K times its samples, so it has no share in the
    // low reading above (on rare bright samples whose truth is known, 16
    // groups read 0.963 of it where a group's own estimate reads 0.55:
    // tests/render/test_film.cpp). The object's pixels are those of all the
    // groups together. Throws jade::Error unless there are at least two
    // groups, of one size, with equally many samples in every pixel.
    static double relative_error_across(const std::vector<Film>& groups);

    // Linear RGBA floats, row 0 at the top; alpha = coverage when
    // `alpha_is_coverage`, else 1.
    std::vector<float> rgba(bool alpha_is_coverage) const;

    // The film's exact state: per pixel (row-major) Σx and Σx² per channel as
    // fixed-point integers in 2^-64 units, the sample count and the count of
    // samples that met the object; and Σx per channel and the sample count of
    // strata 1 … kStrata − 1 (stratum 0 holds the rest), and the same of
    // replicates 1 … kReplicates − 1. What a piece of a split render stores
    // (app/render_piece.h), so that merging pieces read back from disk is as
    // exact as merging them in memory.
    struct Sums {
        int width = 0, height = 0;
        std::vector<__int128> sum, sum_sq;  // 3 per pixel
        std::vector<std::uint32_t> count, hits;
        std::vector<__int128> stratum_sum;         // 3 (kStrata − 1) per pixel
        std::vector<std::uint32_t> stratum_count;  // kStrata − 1 per pixel
        std::vector<__int128> replicate_sum;         // 3 (kReplicates − 1) per pixel
        std::vector<std::uint32_t> replicate_count;  // kReplicates − 1 per pixel
    };
    const std::vector<__int128>& sums() const { return sum_; }
    const std::vector<__int128>& sums_of_squares() const { return sum_sq_; }
    const std::vector<std::uint32_t>& counts() const { return count_; }
    const std::vector<std::uint32_t>& object_hits() const { return hits_; }
    const std::vector<__int128>& stratum_sums() const { return stratum_sum_; }
    const std::vector<std::uint32_t>& stratum_counts() const { return stratum_count_; }
    const std::vector<__int128>& replicate_sums() const { return replicate_sum_; }
    const std::vector<std::uint32_t>& replicate_counts() const { return replicate_count_; }
    // A film holding exactly these sums (throws jade::Error when the sizes
    // disagree or a pixel has more object hits than samples).
    static Film from_sums(Sums sums);
    // The sums of no samples on a film of this size, to be added to.
    static Sums zero_sums(int width, int height);

private:
    std::size_t index(int x, int y) const { return std::size_t(y) * width_ + x; }
    double sum(std::size_t i, int c) const;
    double sum_sq(std::size_t i, int c) const;
    int strata(std::size_t i, int c, double* sums, std::uint32_t* counts) const;
    double pixel_mean(std::size_t i, int c) const;
    double mean_variance(std::size_t i, int c) const;
    double sample_variance(std::size_t i, int c) const;
    // The root of the mean, over the object's pixels (object(i)) and the
    // channels, of variance(i, c) / (mean(i, c)² + ε), ε 0.01 × the square
    // of mean()'s average over those pixels: the rule both measures share.
    template <class Object, class Mean, class Variance>
    static double relative_error(std::size_t pixels, Object object, Mean mean, Variance variance);

    int width_, height_;
    // Σx and Σx² per pixel and channel as fixed-point integers (2^-64 units):
    // integer sums do not depend on the order samples arrive in, which
    // floating-point sums do. A float sample ≥ 2^-40 is held exactly.
    std::vector<__int128> sum_, sum_sq_;  // 3 per pixel
    std::vector<std::uint32_t> count_, hits_;
    std::vector<__int128> stratum_sum_;         // strata 1 …, 3 per stratum and pixel
    std::vector<std::uint32_t> stratum_count_;  // strata 1 …, per pixel
    std::vector<__int128> replicate_sum_;         // replicates 1 …, 3 per replicate and pixel
    std::vector<std::uint32_t> replicate_count_;  // replicates 1 …, per pixel
};

// The same samples on a film `factor` times coarser in each direction: a
// pixel holds every sample of the factor × factor pixels it covers. Pixels
// are boxes (above), so this is the film a camera of that size and framing
// would hold had it drawn these samples itself; the sums are exact, so
// nothing is rounded. Strata are kept, so the variance is still taken within
// them (and includes the spread between the fine pixels: an upper bound).
// Throws jade::Error unless factor ≥ 1 divides both sides.
Film box_downsampled(const Film& film, int factor);

// Error of a film against a reference image of the same size (RGB or more).
struct ReferenceError {
    double rmse = 0.0;     // over all pixels and channels
    double rel_mse = 0.0;  // mean of (x − ref)² / (ref² + 0.01)
};
ReferenceError compare_with_reference(const Film& film, const ImageF32& reference);

}  // namespace jade

namespace jade {

// Writes the film's mean as linear float RGBA (.exr: RGB associated with the
// alpha as OpenEXR expects; alpha = coverage when `alpha_is_coverage`, else 1)
// and, when png_path is not empty, as 8-bit sRGB RGBA (unassociated, as PNG
// expects). Each file is written whole or not at all.
// The PNG is display-encoded after multiplying by `png_exposure`.
void write_film(const Film& film, const std::string& exr_path, const std::string& png_path,
                bool alpha_is_coverage, float png_exposure = 1.f);

}  // namespace jade
