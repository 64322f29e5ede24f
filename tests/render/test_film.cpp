// The film's statistics against their textbook definitions.

#include "jade/render/film.h"
#include "jade/core/error.h"
#include "jade/core/random.h"

#include "support/render_test_util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

using namespace jade;

namespace {
// Two films hold the same exact state: every sum and count.
void check_same_sums(const Film& a, const Film& b) {
    CHECK(a.sums() == b.sums());
    CHECK(a.sums_of_squares() == b.sums_of_squares());
    CHECK(a.counts() == b.counts());
    CHECK(a.object_hits() == b.object_hits());
    CHECK(a.stratum_sums() == b.stratum_sums());
    CHECK(a.stratum_counts() == b.stratum_counts());
    CHECK(a.replicate_sums() == b.replicate_sums());
    CHECK(a.replicate_counts() == b.replicate_counts());
}
}  // namespace

TEST_CASE("the film keeps each pixel's mean, variance of the mean and coverage", "[film]") {
    Film f(2, 1);
    const float values[] = {1.f, 2.f, 4.f, 5.f};
    for (float v : values) f.add_sample(0, 0, Spectrum(v, 2 * v, 0.f), v > 1.5f);
    CHECK(f.mean(0, 0).x == Approx(3.0));
    // Sample variance (n − 1): ((−2)² + (−1)² + 1² + 2²) / 3 = 10/3; of the mean: / 4.
    CHECK(f.variance_of_mean(0, 0).x == Approx(10.0 / 12.0));
    CHECK(f.variance_of_mean(0, 0).y == Approx(40.0 / 12.0));
    CHECK(f.variance_of_mean(0, 0).z == 0.f);
    CHECK(f.coverage(0, 0) == Approx(0.75));
    CHECK(f.coverage(1, 0) == 0.f);
}

// Truth from x87 extended precision: a float times 2^64 is exact in a long
// double's 64-bit significand, and libgcc's long double conversion to
// __int128 is a path of its own.
TEST_CASE("the film's sums hold each sample (and its square) times 2^64 rounded to the nearest integer exactly",
          "[film]") {
    auto exact = [](double v) {  // a float, or a float's square (exact in a double)
        const long double x = std::ldexp(static_cast<long double>(v), 64);
        const long double limit = std::ldexp(1.0L, 126);  // the film clamps at 2^62
        return __int128(std::nearbyintl(std::clamp(x, -limit, limit)));
    };
    std::vector<float> values = {0.f, 1.f, -1.f, std::ldexp(1.f, -64), std::ldexp(1.f, -65),
                                 std::ldexp(3.f, -65), std::ldexp(5.f, -66), -std::ldexp(3.f, -65),
                                 std::ldexp(1.f, 62), 1e30f, -1e30f, 0.1f, 12345.678f};
    SplitMix64 rng(7);
    for (int i = 0; i < 2000; ++i) {
        const float mantissa = float(1.0 + rng.uniform());
        const int exponent = int(rng.below(161)) - 90;  // 2^-90 to 2^70
        values.push_back((rng.uniform() < 0.5 ? -1.f : 1.f) * std::ldexp(mantissa, exponent));
    }
    for (float v : values) {
        Film f(1, 1);
        f.add_sample(0, 0, Spectrum(v, 0.f, 0.f), false);
        INFO("v = " << v);
        CHECK(f.sums()[0] == exact(v));
        CHECK(f.sums_of_squares()[0] == exact(double(v) * double(v)));
        CHECK(f.sums()[1] == 0);
    }
}

TEST_CASE("the estimated relative error predicts the actual error", "[film]") {
    // Pixels of true value 5 with uniform noise of unit width: the estimate
    // from the film's variance must match the RMS relative error against the
    // truth. (A bright value keeps the noise of the denominator m² negligible.)
    const int w = 64, h = 64, spp = 16;
    Film f(w, h), dim(w, h);
    SplitMix64 rng(3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int s = 0; s < spp; ++s) {
                const float v = 5.f + float(rng.uniform() - 0.5);
                f.add_sample(x, y, Spectrum(v), true);
                dim.add_sample(x, y, Spectrum(v / 1000.f), true);
            }
    // The regulariser is 0.01 m̄², m̄ = 5 the image's mean.
    double actual = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double m = f.mean(x, y).x;
            actual += (m - 5.0) * (m - 5.0) / (m * m + 0.01 * 25.0);
        }
    actual = std::sqrt(actual / (w * h));
    // Var of one sample 1/12 -> of the mean 1/192; relative: sqrt(1/192 / 25.25) = 0.014362.
    CHECK(f.estimated_relative_error() == Approx(0.014362).epsilon(0.02));
    // The actual error of 4096 pixels is itself known to ~1.1% (one sigma).
    CHECK(actual == Approx(f.estimated_relative_error()).epsilon(0.05));
    // The same image 1000 times darker is no more exact.
    CHECK(dim.estimated_relative_error() == Approx(f.estimated_relative_error()).epsilon(1e-3));
}

TEST_CASE("the error against a reference is the RMSE", "[film]") {
    Film f(1, 2);
    f.add_sample(0, 0, Spectrum(1.f), true);
    f.add_sample(0, 1, Spectrum(0.f), false);
    ImageF32 ref;
    ref.width = 1;
    ref.height = 2;
    ref.channels = 3;
    ref.pixels = {0.5f, 0.5f, 0.5f, 0.f, 0.f, 0.f};
    const ReferenceError e = compare_with_reference(f, ref);
    CHECK(e.rmse == Approx(std::sqrt(0.25 * 3 / 6)));
    CHECK(e.rel_mse == Approx(0.25 / 0.26 * 3 / 6));
    ref.width = 2;
    CHECK_THROWS(compare_with_reference(f, ref));
}

TEST_CASE("the variance of a stratified pixel's mean is taken within its strata", "[film]") {
    // Three strata of means 1, 5 and 9, each with uniform noise of unit
    // width (variance 1/12), 30 samples a pixel taking the strata in turn
    // from a random start: the mean's variance is 30 · (1/12) / 30² = 1/360.
    // Counted as independent samples, the spread between the strata (32/3
    // per sample) would make it 0.36. Over 4096 pixels the estimates'
    // average has a relative standard deviation of about 0.4 % (each one's
    // is √(2/27)), the means' empirical variance about 2.2 %: 5 of each allowed.
    const int w = 64, h = 64, n = 30;
    Film f(w, h);
    SplitMix64 rng(5);
    const double mu[3] = {1.0, 5.0, 9.0};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int start = int(rng.below(3));
            for (int s = 0; s < n; ++s) {
                const int stratum = (start + s) % 3;
                f.add_sample(x, y, Spectrum(float(mu[stratum] + rng.uniform() - 0.5)), true, stratum);
            }
        }
    double estimated = 0.0, spread = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            estimated += f.variance_of_mean(x, y).x;
            const double d = f.mean(x, y).x - 5.0;
            spread += d * d;
        }
    estimated /= w * h;
    spread /= w * h;
    CHECK(estimated == Approx(1.0 / 360.0).epsilon(0.021));
    CHECK(spread == Approx(1.0 / 360.0).epsilon(0.11));
    // Merged from two halves, the strata's sums add up as the film's do.
    Film a(1, 1), b(1, 1), whole(1, 1);
    for (int s = 0; s < 12; ++s) {
        const float v = float(mu[s % 3] + 0.1 * s);
        (s < 5 ? a : b).add_sample(0, 0, Spectrum(v), true, s % 3);
        whole.add_sample(0, 0, Spectrum(v), true, s % 3);
    }
    a.merge(b);
    CHECK(a.stratum_sums() == whole.stratum_sums());
    CHECK(a.stratum_counts() == whole.stratum_counts());
    CHECK(a.variance_of_mean(0, 0).x == whole.variance_of_mean(0, 0).x);
}

TEST_CASE("a film of one stratum keeps the sample variance over n", "[film]") {
    Film f(1, 1);
    for (float v : {1.f, 2.f, 4.f, 7.f}) f.add_sample(0, 0, Spectrum(v), true);
    // Sample variance of 1, 2, 4, 7: mean 3.5, Σ(x − m)² = 21, / 3 = 7; over n = 4: 1.75.
    CHECK(f.variance_of_mean(0, 0).x == Approx(1.75));
    // Too few samples a stratum to pool within them: the sample variance, the safe side.
    Film g(1, 1);
    for (int s = 0; s < 4; ++s) g.add_sample(0, 0, Spectrum(float(s * s)), true, s % 3);
    // Samples 0, 1, 4, 9 in strata 0, 1, 2, 0: mean 3.5, Σ(x − m)² = 49, / 3, over n = 4.
    CHECK(g.variance_of_mean(0, 0).x == Approx(49.0 / 12.0));
}

TEST_CASE("a film's variance comes from the spread between its replicates once each holds a turn", "[film]") {
    // Samples dealt as the renderer deals them: turn t (samples 3t … 3t + 2,
    // heroes 0, 1, 2) to replicate t mod 4; replicate r's samples are all
    // r + 1, so within a replicate there is no spread at all. With a turn in
    // each (12 samples): replicate means 1, 2, 3, 4, Σx/n 2.5, and
    // R/(R − 1) Σ_r (n_r/n)² (Y_r − 2.5)² = 4/3 · (1/16) · 5 = 5/12.
    const auto add = [](Film& f, int samples) {
        for (int s = 0; s < samples; ++s) {
            const int r = (s / 3) % Film::kReplicates;
            f.add_sample(0, 0, Spectrum(float(r + 1)), true, s % 3, r);
        }
    };
    Film f(1, 1);
    add(f, 12);
    CHECK(f.variance_of_mean(0, 0).x == Approx(5.0 / 12.0));
    // Unequal replicates (15 samples: replicate 0 holds 6, mean 1): shares
    // 6/15 and 3/15 each, Σx/n = (6 + 6 + 9 + 12)/15 = 2.2, and
    // 4/3 · Σ_r (n_r/15)² (Y_r − 2.2)².
    Film g(1, 1);
    add(g, 15);
    const double m = 33.0 / 15.0;
    const double expected = 4.0 / 3.0 *
                            ((0.4 * 0.4) * (1 - m) * (1 - m) + 0.04 * ((2 - m) * (2 - m) + (3 - m) * (3 - m) + (4 - m) * (4 - m)));
    CHECK(g.variance_of_mean(0, 0).x == Approx(expected));
    // Before every replicate holds a turn (11 samples: replicate 3 holds 2):
    // from the samples within the hero strata, as if independent.
    Film h(1, 1);
    add(h, 11);
    CHECK(h.variance_of_mean(0, 0).x == jade_test::without_replicates(h).variance_of_mean(0, 0).x);
}

TEST_CASE("a film's replicates give the pixel's mean from disjoint sets of its samples", "[film]") {
    // Dealt as the renderer deals them (turn t to replicate t mod 4),
    // replicate r's samples all r + 1: 15 samples, replicate 0 holding 6.
    Film f(1, 1);
    for (int s = 0; s < 15; ++s) {
        const int r = (s / 3) % Film::kReplicates;
        f.add_sample(0, 0, Spectrum(float(r + 1), float(2 * (r + 1)), 0.f), true, s % 3, r);
    }
    CHECK(f.replicates_mean(0, 0, 0, 2).x == Approx((6.0 * 1 + 3.0 * 2) / 9.0));
    CHECK(f.replicates_mean(0, 0, 0, 2).y == Approx(2.0 * (6.0 * 1 + 3.0 * 2) / 9.0));
    CHECK(f.replicates_mean(0, 0, 2, 2).x == Approx(3.5));
    CHECK(f.replicates_mean(0, 0, 3, 1).x == Approx(4.0));
    // All four: Σx / n.
    CHECK(f.replicates_mean(0, 0, 0, Film::kReplicates).x == Approx(33.0 / 15.0));
    // Replicates without samples read 0.
    Film g(1, 1);
    g.add_sample(0, 0, Spectrum(1.f), true, 0, 0);
    CHECK(g.replicates_mean(0, 0, 1, 3).x == 0.f);
    CHECK_THROWS_AS(f.replicates_mean(0, 0, 3, 2), Error);
    CHECK_THROWS_AS(f.replicates_mean(0, 0, -1, 1), Error);
}

// K films of n samples each per pixel, sample s of group k being value(rng).
template <class Value>
std::vector<Film> groups_of(int k, int n, int w, int h, Value value) {
    std::vector<Film> groups;
    SplitMix64 rng(11);
    for (int g = 0; g < k; ++g) {
        Film f(w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int s = 0; s < n; ++s) f.add_sample(x, y, Spectrum(value(rng)), true);
        groups.push_back(std::move(f));
    }
    return groups;
}

// Pixels whose samples are b, plus V with probability p: a group of n
// samples holds c ~ Binomial(n, p) of them, and both measures are functions
// of the counts. Their expectations are binomial sums, exact.
struct RareSamples {
    int n = 16;
    double p = 1.0 / 64.0, b = 1.0, V = 20.0;
    double mu() const { return b + p * V; }
    double epsilon() const { return 0.01 * mu() * mu(); }  // 0.01 m̄², m̄ → μ over many pixels
    std::vector<double> pmf() const {
        std::vector<double> q(std::size_t(n) + 1);
        for (int c = 0; c <= n; ++c)
            q[std::size_t(c)] = std::exp(std::lgamma(n + 1.0) - std::lgamma(c + 1.0) - std::lgamma(n - c + 1.0)) *
                                std::pow(p, c) * std::pow(1.0 - p, n - c);
        return q;
    }
    // The relative error of one group's mean.
    double truth() const { return std::sqrt(p * (1.0 - p) * V * V / n / (mu() * mu() + epsilon())); }
    // E of a group's own estimate squared: the sample variance of its mean
    // over its own mean² + ε.
    double own_squared() const {
        const std::vector<double> q = pmf();
        double e = 0.0;
        for (int c = 1; c <= n; ++c) {  // without an event the variance is 0
            const double m = b + c * V / n, s2 = V * V * c * (n - c) / (double(n) * (n - 1));
            e += q[std::size_t(c)] * s2 / n / (m * m + epsilon());
        }
        return e;
    }
    // E across k groups: (Σ c, Σ c²) over the groups, summed out group by group.
    double across_squared(int k) const {
        const std::vector<double> q = pmf();
        std::map<std::pair<int, int>, double> state{{{0, 0}, 1.0}};
        for (int g = 0; g < k; ++g) {
            std::map<std::pair<int, int>, double> next;
            for (const auto& [s, w] : state)
                for (int c = 0; c <= n; ++c)
                    if (w * q[std::size_t(c)] > 1e-18) next[{s.first + c, s.second + c * c}] += w * q[std::size_t(c)];
            state.swap(next);
        }
        double e = 0.0;
        for (const auto& [s, w] : state) {
            const double m = b + s.first * V / (double(n) * k);
            const double var = (V / n) * (V / n) * (s.second - double(s.first) * s.first / k) / (k - 1);
            e += w * var / (m * m + epsilon());
        }
        return e;
    }
};

TEST_CASE("the error measured across groups of samples has no share in the low reading of rare bright samples",
          "[film]") {
    const int k = 16, w = 64, h = 64;
    const RareSamples rare;
    const std::vector<Film> groups = groups_of(
        k, rare.n, w, h, [&](SplitMix64& rng) { return float(rare.b + (rng.uniform() < rare.p ? rare.V : 0.0)); });
    // Across 16 groups the expectation is 0.963 of the truth (the
    // denominators' mean of 256 samples is noisy too; the shortfall falls
    // as 1/(k·n)). Each pixel's variance comes from 16 group means (excess
    // kurtosis of a group mean 59/16): over 4096 pixels the measure is known
    // to 0.5 % in error, one sigma; 2.5 % is 5 sigma.
    const double across = std::sqrt(rare.across_squared(k));
    CHECK(across / rare.truth() == Approx(0.963).epsilon(0.002));
    CHECK(Film::relative_error_across(groups) == Approx(across).epsilon(0.025));
    // A group's own estimate divides the variance a rare sample brings by
    // the mean it inflated: in expectation 0.55 of the truth. Each group's
    // is known to about 2 % (one sigma), the mean of 16 to 0.5 %.
    const double own = std::sqrt(rare.own_squared());
    CHECK(own / rare.truth() == Approx(0.549).epsilon(0.002));
    double measured = 0.0;
    for (const Film& f : groups) measured += f.estimated_relative_error() / k;
    CHECK(measured == Approx(own).epsilon(0.025));
}

TEST_CASE("the error across groups agrees with the film's own estimate where the noise is light", "[film]") {
    // Pixels of value 5 with uniform noise of unit width (the test above of
    // the film's estimate): Var of one sample 1/12, relative error of a
    // group's mean sqrt(1/12 / 16 / 25.25) = 0.014362 (the 8 groups'
    // variance per pixel has 7 degrees of freedom: over 4096 pixels the
    // mean is known to 0.3 % in error).
    const std::vector<Film> groups = groups_of(8, 16, 64, 64, [](SplitMix64& rng) { return float(5.0 + (rng.uniform() - 0.5)); });
    CHECK(Film::relative_error_across(groups) == Approx(0.014362).epsilon(0.02));
    CHECK(Film::relative_error_across(groups) == Approx(groups[0].estimated_relative_error()).epsilon(0.04));
    CHECK_THROWS(Film::relative_error_across({groups[0]}));
    Film fewer(64, 64);
    fewer.add_sample(0, 0, Spectrum(1.f), true);
    CHECK_THROWS(Film::relative_error_across({groups[0], fewer}));
}

TEST_CASE("a box-downsampled film holds exactly the sums of the samples dealt to its coarse pixels", "[film]") {
    // Truth: each sample dealt straight to the coarse pixel its fine pixel
    // lies in, on a film of that size.
    constexpr int kFactor = 3;
    Film fine(6, 9), coarse(2, 3);
    SplitMix64 rng(11);
    for (int n = 0; n < 4000; ++n) {
        const int x = int(rng.below(6)), y = int(rng.below(9));
        const Spectrum v(float(rng.uniform()), float(3.0 * rng.uniform()), float(rng.uniform() * rng.uniform()));
        const bool hit = rng.uniform() < 0.7;
        const int stratum = int(rng.below(Film::kStrata));
        fine.add_sample(x, y, v, hit, stratum);
        coarse.add_sample(x / kFactor, y / kFactor, v, hit, stratum);
    }
    const Film down = box_downsampled(fine, kFactor);
    REQUIRE(down.width() == 2);
    REQUIRE(down.height() == 3);
    check_same_sums(down, coarse);
    CHECK_THROWS_AS(box_downsampled(fine, 4), Error);
    CHECK_THROWS_AS(box_downsampled(fine, 0), Error);
}

TEST_CASE("samples of one value added at once leave the sums of as many single samples", "[film]") {
    // The renderer adds a pixel's backdrop samples so (render/renderer.h,
    // pixels_seeing); the film must not tell them apart.
    SplitMix64 rng(11);
    for (int trial = 0; trial < 50; ++trial) {
        const Spectrum v(float(rng.uniform() * 3.0), float(std::ldexp(rng.uniform(), -40)), float(-rng.uniform()));
        const int replicate = int(rng.below(Film::kReplicates));
        std::array<std::uint32_t, Film::kStrata> per_stratum{};
        for (auto& n : per_stratum) n = std::uint32_t(rng.below(7));
        Film one(3, 2), many(3, 2);
        many.add_samples(1, 1, v, per_stratum, replicate);
        for (int s = 0; s < Film::kStrata; ++s)
            for (std::uint32_t k = 0; k < per_stratum[std::size_t(s)]; ++k) one.add_sample(1, 1, v, false, s, replicate);
        check_same_sums(one, many);
    }
}
