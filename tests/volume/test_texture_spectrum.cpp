// Texture spectra against images whose structure is known exactly: a
// sinusoid has all its variance at one frequency and one direction.

#include "jade/core/math.h"
#include "jade/core/random.h"
#include "jade/volume/texture_spectrum.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jade;

namespace {

// A sinusoid of `cycles` per image width whose wave vector points `degrees`
// counterclockwise from the displayed horizontal (y up on screen), plus white
// noise of standard deviation `sigma`.
GrayImage sinusoid(int n, double cycles, double degrees_, double sigma = 0.0, std::uint64_t seed = 42) {
    GrayImage g;
    g.width = g.height = n;
    g.values.resize(std::size_t(n) * n);
    const double kx = std::cos(radians(degrees_)), ky = std::sin(radians(degrees_));
    SplitMix64 rng(seed);
    for (int row = 0; row < n; ++row)
        for (int x = 0; x < n; ++x) {
            const double y_up = n - 1 - row;
            double v = 100.0 + 50.0 * std::sin(2.0 * kPiD * cycles * (kx * x + ky * y_up) / n);
            if (sigma > 0.0) {  // Box–Muller
                const double u1 = std::max(1e-300, to_unit_double(rng.next()));
                const double u2 = to_unit_double(rng.next());
                v += sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPiD * u2);
            }
            g.values[std::size_t(row) * n + x] = float(v);
        }
    return g;
}

// Seeds this far apart give images of independent noise: SplitMix64's
// stream from seed s + 1 is the one from s a draw later, and an image takes
// 2·256² draws.
constexpr std::uint64_t kApart = 1'000'000;

int band_of(double cycles_per_side) { return int(std::floor(2.0 * std::log2(cycles_per_side))); }

}  // namespace

TEST_CASE("texture spectrum: a sinusoid's variance lies in its band, across its stripes", "[spectrum]") {
    const TextureSpectrum sp = texture_spectrum(sinusoid(256, 20.0, 30.0), 256.0);
    REQUIRE(sp.square == 256);
    REQUIRE(sp.power[band_of(20.0)] > 0.95);
    // The stripes run perpendicular to the wave vector.
    REQUIRE(orientation_difference(sp.orientation, 120.0) < 1.0);
    REQUIRE(sp.strength > 0.95);
    REQUIRE(sp.coherence > 0.95);
}

TEST_CASE("texture spectrum: frequencies are per cube side, whatever the pixel count", "[spectrum]") {
    // 20 cycles across an image that spans half a side: 40 cycles per side.
    const TextureSpectrum sp = texture_spectrum(sinusoid(256, 20.0, 0.0), 512.0);
    REQUIRE(sp.power[band_of(40.0)] > 0.95);
    REQUIRE(orientation_difference(sp.orientation, 90.0) < 1.0);
}

TEST_CASE("texture spectrum: a known white-noise variance is taken out", "[spectrum]") {
    // Noise of σ = 100 has 8x the sinusoid's variance (50²/2): left in, it
    // spreads over every band; taken out, the sinusoid's band holds nearly all.
    const GrayImage noisy = sinusoid(256, 20.0, 0.0, 100.0);
    const TextureSpectrum raw = texture_spectrum(noisy, 256.0);
    const TextureSpectrum clean = texture_spectrum(noisy, 256.0, 100.0 * 100.0);
    REQUIRE(raw.power[band_of(20.0)] < 0.3);
    REQUIRE(clean.power[band_of(20.0)] > 0.6);
}

TEST_CASE("cross spectrum: noise the two images do not share averages out", "[spectrum]") {
    // Two copies of one sinusoid (variance 50²/2 = 1250) with independent
    // noise of σ = 100 (8x its variance), as two halves of a render's
    // samples are. Parseval: the sinusoid puts N·1250·W into its band (N =
    // 256² bins, W the window energy); a bin of the cross-periodogram holds
    // the noises' product, of mean 0 and standard deviation σ²W/√2, so a
    // band of B bins is off by σ²W·√(B/2), at most 90·σ²W (B ≤ N/4) and
    // summed over the 14 bands' positive parts at most ~500·σ²W, 6 % of the
    // sinusoid's power. The periodogram of one copy carries N·σ²W of noise,
    // 8x the sinusoid's.
    const GrayImage a = sinusoid(256, 20.0, 30.0, 100.0, kApart), b = sinusoid(256, 20.0, 30.0, 100.0, 2 * kApart);
    const TextureSpectrum one = texture_spectrum(a, 256.0);
    const TextureSpectrum shared = texture_cross_spectrum(a, b, 256.0);
    CHECK(one.power[band_of(20.0)] < 0.3);
    CHECK(shared.power[band_of(20.0)] > 0.9);
    CHECK(orientation_difference(shared.orientation, 120.0) < 2.0);
    CHECK(structure_distance(shared, texture_spectrum(sinusoid(256, 20.0, 30.0), 256.0)) <
          structure_distance(one, texture_spectrum(sinusoid(256, 20.0, 30.0), 256.0)));
    // Of one image with itself it is the periodogram.
    const TextureSpectrum self = texture_cross_spectrum(a, a, 256.0);
    for (int band = 0; band < TextureSpectrum::kBands; ++band) CHECK(self.power[band] == Approx(one.power[band]));
    CHECK(self.coherence == Approx(one.coherence));
}

namespace {

// White noise of standard deviation `sigma` about 100, nothing else.
GrayImage white(int n, double sigma, std::uint64_t seed) {
    GrayImage g = sinusoid(n, 1.0, 0.0, sigma, seed);
    const GrayImage flat = sinusoid(n, 1.0, 0.0);
    for (std::size_t i = 0; i < g.values.size(); ++i) g.values[i] -= flat.values[i] - 100.0f;
    return g;
}

}  // namespace

TEST_CASE("cross spectrum: the bands' standard error is the noise's", "[spectrum]") {
    // Two halves of pure noise share nothing: each band's cross power is the
    // noises' product, about 0, over the standard error the spectrum states
    // z ~ N(0, 1), so z > 1 in 15.9 % of the bands and z > 2 in 2.3 %. Over
    // 40 pairs of 12 bands those shares are known to ±0.017 and ±0.007; the
    // bounds are 4 of those from them and would catch an error misjudged by
    // half. A band is below the noise unless z > 3.
    auto tally = [](const TextureSpectrum& s, int& bands, int& over_one, int& over_two, int& below) {
        for (int b = 0; b < TextureSpectrum::kBands; ++b) {
            if (s.power[b] < 0.0) continue;
            REQUIRE(s.error[b] > 0.0);
            const double z = s.power[b] / s.error[b];
            ++bands, over_one += z > 1.0, over_two += z > 2.0, below += s.below_noise[b];
            CHECK(s.below_noise[b] == (z < TextureSpectrum::kDetection));
        }
    };
    int bands = 0, over_one = 0, over_two = 0, below = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed)
        tally(texture_cross_spectrum(white(256, 30.0, kApart * seed), white(256, 30.0, kApart * seed + kApart / 2), 256.0),
              bands, over_one, over_two, below);
    REQUIRE(bands == 40 * 12);
    CHECK(double(over_one) / bands == Approx(0.159).margin(0.07));
    CHECK(double(over_two) / bands < 0.05);
    CHECK(double(below) / bands > 0.99);
    // One image less a known floor: the same for the floor's noise.
    bands = over_one = over_two = below = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed)
        tally(texture_spectrum(white(256, 30.0, kApart * seed), 256.0, 30.0 * 30.0), bands, over_one, over_two, below);
    CHECK(double(over_one) / bands == Approx(0.159).margin(0.07));
    CHECK(double(over_two) / bands < 0.05);
    // An image without noise has no error and no band under it.
    const TextureSpectrum clean = texture_spectrum(white(256, 30.0, 7), 256.0);
    for (int b = 0; b < TextureSpectrum::kBands; ++b) CHECK((clean.error[b] == 0.0 && !clean.below_noise[b]));
}

TEST_CASE("cross spectrum: the bands under the noise are flagged, and compared as measured", "[spectrum]") {
    // The sinusoid of "noise the two images do not share" under noise of 8x
    // its variance: every band but its own is under the noise, for every
    // pair of halves, and says so; the distance takes the shares as they
    // were measured, whatever the flags.
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
        const TextureSpectrum shared = texture_cross_spectrum(sinusoid(256, 20.0, 30.0, 100.0, kApart * seed),
                                                              sinusoid(256, 20.0, 30.0, 100.0, kApart * seed + kApart / 2),
                                                              256.0);
        CHECK(!shared.below_noise[band_of(20.0)]);
        CHECK(shared.bands_below_noise() == shared.measured_bands() - 1);
        TextureSpectrum unflagged = shared;
        unflagged.below_noise.fill(false);
        const TextureSpectrum truth = texture_spectrum(sinusoid(256, 20.0, 30.0), 256.0);
        CHECK(structure_distance(shared, truth) == structure_distance(unflagged, truth));
    }
}

TEST_CASE("structure distance: zero for one structure, large for another scale", "[spectrum]") {
    const TextureSpectrum a = texture_spectrum(sinusoid(256, 20.0, 0.0, 5.0), 256.0);
    const TextureSpectrum b = texture_spectrum(sinusoid(256, 20.0, 60.0, 5.0), 256.0);
    const TextureSpectrum c = texture_spectrum(sinusoid(256, 80.0, 0.0, 5.0), 256.0);
    REQUIRE(structure_distance(a, a) == 0.0);
    REQUIRE(structure_distance(a, b) < 0.1);   // same scale, other direction: the radial spectrum agrees
    REQUIRE(structure_distance(a, c) > 1.0);   // two octaves apart
    REQUIRE(orientation_difference(170.0, 10.0) == Approx(20.0));
    // Held to the bands of a coarser image (a quarter of the pixels per
    // side: its top four bands are gone), c's band at 80 cycles is not
    // compared.
    const TextureSpectrum coarse = texture_spectrum(sinusoid(64, 5.0, 0.0), 64.0);
    const TextureSpectrum c_low = common_bands(c, coarse);
    CHECK(c_low.measured_bands() == coarse.measured_bands());
    CHECK(c_low.power[band_of(80.0)] < 0.0);
}

TEST_CASE("largest inside square: a disc holds a square of side r·√2", "[spectrum]") {
    GrayImage g;
    g.width = g.height = 200;
    g.values.assign(200 * 200, 0.f);
    g.mask.assign(200 * 200, 0);
    const double r = 60.0;
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 200; ++x)
            g.mask[y * 200 + x] = std::hypot(x + 0.5 - 100.0, y + 0.5 - 100.0) <= r;
    const auto sq = largest_inside_square(g);
    REQUIRE(std::abs(sq[2] - r * std::sqrt(2.0)) <= 2.0);
    for (int y = sq[1]; y < sq[1] + sq[2]; ++y)
        for (int x = sq[0]; x < sq[0] + sq[2]; ++x) REQUIRE(g.inside(x, y));
}

namespace {

// An image of n × n whose value at (x, row) is f(x, row).
template <class F> GrayImage image_of(int n, F f) {
    GrayImage g;
    g.width = g.height = n;
    g.values.resize(std::size_t(n) * n);
    for (int row = 0; row < n; ++row)
        for (int x = 0; x < n; ++x) g.values[std::size_t(row) * n + x] = float(f(double(x), double(row)));
    return g;
}

}  // namespace

TEST_CASE("orientation defects: none where stripes fold, two half-turns where rings close, many in noise", "[spectrum]") {
    constexpr int n = 256;  // blocks of 8 px, a 32nd of the side: 31 × 31 blocks, 30 × 30 cells between them
    constexpr double cells = 30.0 * 30.0;
    // Stripes displaced along y by a fold of up to 1.2 stripe spacings
    // (limbs tilted up to 60°): the layer coordinate rises monotonically
    // across the stripes, so the orientation never turns around a point.
    const GrayImage folded = image_of(n, [](double x, double row) {
        return 100.0 + 50.0 * std::sin(2.0 * kPiD * (12.0 * row / n + 1.2 * std::sin(2.0 * kPiD * 2.0 * x / n)));
    });
    const TextureSpectrum f = texture_spectrum(folded, n);
    CHECK(f.defects == 0.0);
    CHECK(f.coherence > 0.9);
    // Concentric rings: the orientation turns a whole turn around their
    // centre. The blocks' grid splits it into two half-turn defects in cells
    // beside it, wherever the centre lies (measured for four centres; the
    // four blocks around it see a quarter of the rings each, and their
    // doubled angles step by half a turn, which no loop can count twice).
    const GrayImage rings = image_of(n, [](double x, double row) {
        const double r = std::hypot(x - 130.1, row - 127.3);
        return 100.0 + 50.0 * std::sin(2.0 * kPiD * r / 20.0);
    });
    const TextureSpectrum r = texture_spectrum(rings, n);
    CHECK(r.defects * cells == Approx(2.0));
    // White noise: every block's orientation is its own draw, and a loop of
    // four independent uniform doubled angles winds about a third of the
    // time (0.34 for this seed), against none above.
    const GrayImage noise = sinusoid(n, 20.0, 0.0, 1e4);
    CHECK(texture_spectrum(noise, n).defects > 0.2);
}

TEST_CASE("orientation defects: blocks without an orientation are left out of the count", "[spectrum]") {
    // Flat grey but for three blocks of fine stripes (blocks of 8 px from
    // pixel 1) whose gradients point at 45°, 90° and 135°: doubled, 90°,
    // 180° and 270°. The fourth block of their cell is flat, its angle
    // undefined (atan2(0, 0) = 0); read as 0 the loop would turn a whole
    // doubled turn and count a defect that no orientation field has.
    constexpr int n = 256;
    auto stripes = [](double x, double row, double degrees_) {
        const double c = std::cos(radians(degrees_)), s = std::sin(radians(degrees_));
        return 100.0 + 50.0 * std::sin(2.0 * kPiD * (c * x + s * row) / 4.0);
    };
    const GrayImage three = image_of(n, [&](double x, double row) {
        const int i = (int(x) - 1) / 8, j = (int(row) - 1) / 8;
        if (x >= 1.0 && row >= 1.0) {
            if (i == 11 && j == 10) return stripes(x, row, 45.0);
            if (i == 11 && j == 11) return stripes(x, row, 90.0);
            if (i == 10 && j == 11) return stripes(x, row, 135.0);
        }
        return 100.0;
    });
    CHECK(texture_spectrum(three, n).defects == 0.0);
    // No block has an orientation: no cell is counted, and the share is 0.
    const GrayImage flat = image_of(n, [](double, double) { return 100.0; });
    CHECK(texture_spectrum(flat, n).defects == 0.0);
}

namespace {

// Structure in every band a 256-pixel square measures: one sinusoid at the
// middle of each half-octave band from 2 to 128 cycles, its direction
// turning 50° a band, its amplitude falling as 1/cycles (a power spectrum
// falling as f⁻², as stone photos roughly do), plus white noise of
// standard deviation `sigma`.
GrayImage every_band(int n, double sigma, std::uint64_t seed, double falloff = 1.0) {
    GrayImage g = white(n, sigma, seed);
    for (int b = 2; b < 14; ++b) {
        const double cycles = std::exp2(0.5 * b + 0.25), angle = radians(50.0 * b);
        const double kx = std::cos(angle), ky = std::sin(angle), amplitude = 400.0 / std::pow(cycles, falloff);
        for (int row = 0; row < n; ++row)
            for (int x = 0; x < n; ++x)
                g.values[std::size_t(row) * n + x] +=
                    float(amplitude * std::sin(2.0 * kPiD * cycles * (kx * x + ky * (n - 1 - row)) / n));
    }
    return g;
}

// Over 40 pairs of halves: the distances' standard deviation, and the mean
// of the errors each pair states.
std::pair<double, double> distance_scatter(double sigma, double photo_falloff) {
    const TextureSpectrum truth = texture_spectrum(every_band(256, 0.0, 1, photo_falloff), 256.0);
    double sum = 0.0, sum_sq = 0.0, stated = 0.0;
    constexpr int kPairs = 40;
    for (std::uint64_t seed = 1; seed <= kPairs; ++seed) {
        const TextureSpectrum shared = texture_cross_spectrum(every_band(256, sigma, kApart * seed),
                                                              every_band(256, sigma, kApart * seed + kApart / 2), 256.0);
        const double d = structure_distance(shared, truth);
        sum += d, sum_sq += d * d;
        stated += structure_distance_error(shared, truth);
    }
    const double mean = sum / kPairs;
    return {std::sqrt((sum_sq - kPairs * mean * mean) / (kPairs - 1)), stated / kPairs};
}

}  // namespace

TEST_CASE("structure distance: its stated error is the scatter over independent renders", "[spectrum]") {
    // A render's texture (structure in every band, under noise that leaves
    // 1, 2 and 4 of its 12 bands under the noise) against a photo whose
    // spectrum falls faster, so the distance is 0.4–0.9 as a render's is.
    // The standard deviation of 40 pairs' distances is known to 11 %; the
    // bounds are three of that from 1, so an error misstated by √2 either
    // way fails.
    for (double falloff : {1.25, 1.5})
        for (double sigma : {20.0, 60.0, 120.0}) {
            const auto [scatter, stated] = distance_scatter(sigma, falloff);
            INFO("photo's falloff " << falloff << ", noise " << sigma << ": scatter " << scatter << ", stated " << stated);
            CHECK(stated / scatter > 0.7);
            CHECK(stated / scatter < 1.4);
        }
    // Near a distance of 0 the error is overstated, not understated: the
    // draws about a measured spectrum add a second noise to the first,
    // where about the truth a distance's scatter is the noise's alone
    // (the render's own texture as the photo, noise 20: scatter 0.017,
    // stated 0.033).
    const auto [scatter, stated] = distance_scatter(20.0, 1.0);
    CHECK(stated > scatter);
    // Spectra without noise have no error.
    const TextureSpectrum clean = texture_spectrum(every_band(256, 0.0, 1), 256.0);
    CHECK(structure_distance_error(clean, texture_spectrum(every_band(256, 0.0, 1, 1.5), 256.0)) == 0.0);
}
