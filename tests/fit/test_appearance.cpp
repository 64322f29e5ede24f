// The render's structure against the photo's (fit/appearance.h), on a film
// whose converged image is known: measured on what two independent halves
// of its samples share, the render's noise is neither taken for structure
// nor subtracted beyond what it is.

#include "jade/core/display.h"
#include "jade/core/math.h"
#include "jade/core/random.h"
#include "jade/fit/appearance.h"
#include "jade/fit/display.h"
#include "jade/render/film.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jade;

namespace {

constexpr int kSide = 128;  // pixels across the film, which spans one cube side

// A grey texture with variance in every band a 128-pixel square measures
// (2 to 64 cycles per side): one cosine per half-octave band, at the band's
// middle, each in its own direction, amplitudes falling as f^-1/2 as a
// stone's do. Linear values 0.08–0.32.
double texture(int x, int y) {
    double v = 0.2;
    for (int b = 2; b <= 11; ++b) {
        const double f = std::exp2(0.5 * (b + 0.5)), theta = radians(37.0 * b);
        v += 0.04 / std::sqrt(f) *
             std::cos(2.0 * kPiD * f * (x * std::cos(theta) + y * std::sin(theta)) / kSide + 1.3 * b);
    }
    return v;
}

// `spp` samples a pixel, dealt to strata and replicates as the renderer
// deals them (render/pixel_sampler.h); each channel of a sample is the
// texture times its own exponential number (mean 1): unbiased, skewed, and
// independent between channels, as a path's three weights are not quite.
Film noisy_film(int spp, std::uint64_t seed) {
    Film f(kSide, kSide);
    SplitMix64 rng(seed);
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) {
            const double t = texture(x, y);
            for (int s = 0; s < spp; ++s) {
                Spectrum v;
                for (int c = 0; c < 3; ++c) v[c] = float(-t * std::log(1.0 - to_unit_double(rng.next())));
                f.add_sample(x, y, v, true, s % 3, (s / 3) % Film::kReplicates);
            }
        }
    return f;
}

}  // namespace

TEST_CASE("render structure: measured on what two halves of the samples share", "[fitter][appearance]") {
    // The truth: the converged texture's spectrum in display levels.
    Film exact(kSide, kSide);
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x)
            for (int s = 0; s < 12; ++s)
                exact.add_sample(x, y, Spectrum(float(texture(x, y))), true, s % 3, (s / 3) % Film::kReplicates);
    const TextureSpectrum truth = texture_spectrum(display_statistics(exact, 1.f).luma, kSide);
    REQUIRE(truth.measured_bands() == 10);
    for (int b = 2; b <= 11; ++b) CHECK(truth.power[b] > 0.0);

    // 288 samples a pixel: a half's luma then has about 1.7 times the finest
    // band's texture variance in noise there, of which the halves' product
    // leaves some 3 % in a band of ~2000 independent bins (the noise of a
    // product of two independent noises over √(B/2)): the distance came to
    // 0.016–0.033 over the seeds below, a band's error under 0.1 decade.
    const RgbHistogram photo_histogram = display_statistics(exact, 1.f).histogram;
    // The halves only where asked for.
    CHECK(display_statistics(exact, 1.f).luma_halves[0].width == 0);
    CHECK(display_statistics(exact, 1.f, LumaHalves::Measure).luma_halves[1].width == kSide);
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        INFO("seed " << seed);
        const DisplayStatistics noisy = display_statistics(noisy_film(288, seed), 1.f, LumaHalves::Measure);
        REQUIRE(noisy.luma_halves[0].width == kSide);
        const Appearance look = compare_appearance(photo_histogram, truth, noisy, kSide);
        // The white floor bounds the luma's noise from above (the channels'
        // noise taken as fully correlated), here 1.8 times its variance
        // (1 / Σ w_c² for luma weights w_c): the finest band, where the
        // noise is 1.7 times the texture, read empty (1.32 for each seed).
        const TextureSpectrum floored = texture_spectrum(noisy.luma, kSide, noisy.luma_noise_variance);
        const double floored_distance = structure_distance(floored, truth);
        INFO("halves " << look.structure << ", subtracted floor " << floored_distance);
        CHECK(look.structure < 0.1);
        CHECK(floored_distance > 0.5);
        for (int b = 2; b <= 11; ++b) CHECK(look.render.power[b] > 0.0);
    }

    // Below a turn of the heroes in every replicate there are no halves, and
    // the floor is subtracted as before.
    const DisplayStatistics few = display_statistics(noisy_film(8, 4), 1.f, LumaHalves::Measure);
    CHECK(few.luma_halves[0].width == 0);
    const Appearance look = compare_appearance(photo_histogram, truth, few, kSide);
    const TextureSpectrum floored = texture_spectrum(few.luma, kSide, few.luma_noise_variance);
    for (int b = 0; b < TextureSpectrum::kBands; ++b) CHECK(look.render.power[b] == floored.power[b]);
}
