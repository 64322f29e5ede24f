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
#include <functional>

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
        // noise is 1.7 times the texture, read empty (1.32 for each seed),
        // and says it is under the noise.
        const TextureSpectrum floored = texture_spectrum(noisy.luma, kSide, noisy.luma_noise_variance);
        const double floored_distance = structure_distance(floored, truth);
        INFO("halves " << look.structure << ", subtracted floor " << floored_distance);
        CHECK(look.structure < 0.1);
        // Its standard error from the halves' noise, which the bands state.
        CHECK(look.structure_error > 0.0);
        CHECK(look.structure_error == structure_distance_error(look.render, truth));
        CHECK(floored.below_noise[11]);
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

namespace {

// A film whose every pixel is the object, its converged value `shade(x, y)`
// in every channel (12 equal samples: no noise).
template <class Shade>
Film shading_film(int side, Shade shade) {
    Film f(side, side);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
            for (int s = 0; s < 12; ++s)
                f.add_sample(x, y, Spectrum(float(shade(x, y))), true, s % 3, (s / 3) % Film::kReplicates);
    return f;
}

Photo photo_of(int side, std::function<Rgb8(int, int)> colour) {
    Photo p;
    p.width = p.height = side;
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) p.levels.push_back(colour(x, y));
    p.foreground.assign(p.levels.size(), 1);
    return p;
}

}  // namespace

TEST_CASE("the photo's stone under a shading: the photo back under even light, two levels under two and the least of any material",
          "[fitter][appearance]") {
    constexpr int kPhoto = 64;
    SECTION("even shading at the photo's own scale gives the photo's levels back") {
        // A texture of many levels per channel; a film of the photo's size
        // spanning one cube side (one render pixel per photo pixel).
        const Photo photo = photo_of(kPhoto, [](int x, int y) {
            return Rgb8{std::uint8_t(60 + (7 * x + 3 * y) % 150), std::uint8_t(90 + (x * y) % 120),
                        std::uint8_t(30 + (5 * x + 11 * y) % 200)};
        });
        const Photo stone = shaded_photo(photo, shading_film(kPhoto, [](int, int) { return 0.37; }), 2.f, kPhoto);
        REQUIRE(stone.foreground_count() == photo.foreground_count());
        int off = 0;
        for (std::size_t i = 0; i < photo.levels.size(); ++i)
            for (int c = 0; c < 3; ++c) off = std::max(off, std::abs(int(stone.levels[i][c]) - int(photo.levels[i][c])));
        CHECK(off <= 1);  // the scale is found by bisection on the continuous mean level
        const RgbHistogram a = RgbHistogram::of(stone.foreground_levels()), b = RgbHistogram::of(photo.foreground_levels());
        for (int c = 0; c < 3; ++c) CHECK(histogram_distance(a, b, c) < 1e-3);
    }
    SECTION("a render pixel averages the photo over its footprint, shares of pixels too") {
        // Columns alternating two colours; 1.5 photo pixels a render pixel:
        // render column 0 covers column 0 and half of 1, column 1 the other
        // half of 1 and column 2, column 2 column 3 and half of 4.
        const double a = srgb_decode(200 / 255.0), b = srgb_decode(40 / 255.0);
        const Photo photo = photo_of(kPhoto, [](int x, int) {
            const std::uint8_t l = x % 2 ? 40 : 200;
            return Rgb8{l, l, l};
        });
        const Photo stone =
            shaded_photo(photo, shading_film(kPhoto, [](int, int) { return 1.0; }), 1.f, kPhoto / 1.5);
        auto linear = [&](int x) { return srgb_decode(stone.levels[std::size_t(x)][1] / 255.0); };
        CHECK(stone.levels[0][1] == stone.levels[1][1]);
        CHECK(linear(0) / linear(2) == Approx((a + 0.5 * b) / (b + 0.5 * a)).epsilon(0.03));
    }
    SECTION("compare_material: under even light the stone is the photo, in histogram and structure") {
        // The texture above as a grey photo of 128², and a render and its
        // shading of that size spanning one cube side.
        const Photo photo = photo_of(kSide, [](int x, int y) {
            const std::uint8_t l = display_level(texture(x, y));
            return Rgb8{l, l, l};
        });
        const Film even = shading_film(kSide, [](int, int) { return 0.5; });
        const SplitFilms halves{even, even, {}};
        const MaterialAppearance m = compare_material(photo, halves, halves, 1.f, kSide);
        for (int c = 0; c < 3; ++c) CHECK(m.d_stone[c] < 1e-3);
        // Even light shows any histogram of levels: some material reaches
        // the photo's exactly.
        for (int c = 0; c < 3; ++c) CHECK(m.d_least[c] >= 0.0);
        for (int c = 0; c < 3; ++c) CHECK(m.d_least[c] < 1e-5);
        CHECK(m.structure_stone >= 0.0);
        CHECK(m.structure_stone < 0.02);
    }
    SECTION("a stone of one colour under two lights: two levels, their mean the photo's, their light 1:3") {
        const Photo photo = photo_of(kPhoto, [](int, int) { return Rgb8{180, 120, 60}; });
        // The left half lit three times as brightly as the right, a render
        // twice the photo's width: each render pixel takes half a photo pixel.
        const Film shading = shading_film(2 * kPhoto, [](int x, int) { return x < kPhoto ? 0.6 : 0.2; });
        const Photo stone = shaded_photo(photo, shading, 1.f, 2 * kPhoto);
        for (int c = 0; c < 3; ++c) {
            const int bright = stone.levels[0][c], dark = stone.levels[std::size_t(2 * kPhoto - 1)][c];
            INFO("channel " << c << ": " << bright << ", " << dark);
            CHECK(std::abs(0.5 * (bright + dark) - photo.levels[0][c]) <= 0.5);
            CHECK(srgb_decode(bright / 255.0) / srgb_decode(dark / 255.0) == Approx(3.0).epsilon(0.06));
            // Half the pixels at each level, none at the photo's: D = 1 + ¼ + ¼.
            const RgbHistogram a = RgbHistogram::of(stone.foreground_levels());
            CHECK(histogram_distance(a, RgbHistogram::of(photo.foreground_levels()), c) == Approx(1.5));
        }
    }
    SECTION("the least D of any material under two lights 10⁴ apart: 3/8") {
        // Any material level shows the dark half at level 0 or the lit half
        // at 255 (or both), and at most half the pixels at the photo's one
        // level L. So the mass at 0 and 255 together is at least ½, at L at
        // most ½: D ≥ (1 − ½)² + u² + (½ − u)² ≥ 3/8. A share α of the
        // material lighting the lit half to L (dark half at 0) and 1 − α the
        // dark half (lit half at 255) has A = L/2 + (1 − α)·127.5, which is
        // the photo's L at α = 1 − L/255: at L = 128 u = α/2 = 0.249 and
        // D = 3/8 + 2·0.001², so that is the least of A = L.
        const Photo photo = photo_of(kPhoto, [](int, int) { return Rgb8{128, 128, 128}; });
        const Film shading = shading_film(2 * kPhoto, [](int x, int) { return x < kPhoto ? 1.0 : 1e-4; });
        const std::array<double, 3> least = least_material_distance(photo, shading, 1.f);
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c);
            // A bound within 1 % of the best mixture found, which is 3/8.
            CHECK(least[c] <= 0.375 + 1e-5);
            CHECK(least[c] >= 0.99 * 0.375);
        }
    }
    SECTION("shading_reach: the stone's D and the least's under one shading, two lights 10⁴ apart") {
        // The photo's one level, scaled to the photo's A (as near as it
        // goes), shows at 255 under the lit half and near 0 under the dark
        // half: D = ¼ + ¼ + 1. The least of any material is the 3/8 above.
        const Photo photo = photo_of(kPhoto, [](int, int) { return Rgb8{128, 128, 128}; });
        const Film shading = shading_film(2 * kPhoto, [](int x, int) { return x < kPhoto ? 1.0 : 1e-4; });
        const ShadingReach r = shading_reach(photo, shading, 1.f, 2 * kPhoto);
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c);
            CHECK(r.d_stone[c] == Approx(1.5));
            CHECK(r.d_least[c] <= 0.375 + 1e-5);
            CHECK(r.d_least[c] >= 0.99 * 0.375);
        }
    }
    SECTION("the least D of a material as like the stone as a given one: two lights 10⁴ apart") {
        // The case above: the least whole-render D, 3/8, takes a material
        // nothing like the one-level stone: its two multipliers are 10⁴
        // apart, and flattened (scaled so that the multiplier whose render
        // alone has A = 128 shows 128) they show levels near 33 and 255. A
        // material whose own histogram is within δ of the photo's holds
        // p₁₂₈ ≥ 1 − √δ of its levels within one of 128, multipliers near
        // that one, which light the lit half at 255 and the dark half near 0,
        // none at 128; the rest puts at most half its pixels there. So the
        // render's mass at 128 is at most √δ/2, and D ≥ (1 − √δ/2)².
        const Photo photo = photo_of(kPhoto, [](int, int) { return Rgb8{128, 128, 128}; });
        const Film shading = shading_film(2 * kPhoto, [](int x, int) { return x < kPhoto ? 1.0 : 1e-4; });
        const std::array<double, 3> free = least_material_distance(photo, shading, 1.f);
        const RgbHistogram levels = RgbHistogram::of(photo.foreground_levels());
        const std::array<double, 3> loose = least_material_distance_as_near(photo, shading, 1.f, {2.0, 2.0, 2.0}, levels);
        const std::array<double, 3> near = least_material_distance_as_near(photo, shading, 1.f, {0.05, 0.05, 0.05}, levels);
        const std::array<double, 3> nearer = least_material_distance_as_near(photo, shading, 1.f, {0.01, 0.01, 0.01}, levels);
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c << ": free " << free[c] << ", δ 2: " << loose[c] << ", δ 0.05: " << near[c]
                            << ", δ 0.01: " << nearer[c]);
            // A ceiling above every material's D is none.
            CHECK(loose[c] == Approx(free[c]).epsilon(0.02));
            CHECK(near[c] >= 0.99 * std::pow(1.0 - std::sqrt(0.05) / 2.0, 2.0));
            CHECK(nearer[c] >= 0.99 * std::pow(1.0 - std::sqrt(0.01) / 2.0, 2.0));
            // Nor more than the one material at the photo's level: half
            // the pixels at 255, half near 0, D = ¼ + ¼ + 1.
            CHECK(near[c] <= 1.5 + 1e-9);
            CHECK(nearer[c] <= 1.5 + 1e-9);
            CHECK(nearer[c] >= near[c] - 1e-3);
        }
        // A channel whose material D was not measured has no bound.
        const std::array<double, 3> partial = least_material_distance_as_near(photo, shading, 1.f, {-1.0, 0.05, 0.05}, levels);
        CHECK(partial[0] == -1.0);
        CHECK(partial[1] == Approx(near[1]));
    }
    SECTION("half the object unlit: the photo's A out of reach, the nearest A instead") {
        // Unlit pixels stay at level 0 whatever the material, so the brightest
        // render (the lit half at 255) has A 127.5, below the photo's 250.
        // At that A only that render: ½ at 0, ½ at 255, none at 250: D = 1.5.
        const Photo photo = photo_of(kPhoto, [](int, int) { return Rgb8{250, 250, 250}; });
        const Film shading = shading_film(2 * kPhoto, [](int x, int) { return x < kPhoto ? 0.5 : 0.0; });
        const std::array<double, 3> least = least_material_distance(photo, shading, 1.f);
        for (int c = 0; c < 3; ++c) {
            CHECK(least[c] <= 1.5 + 1e-9);
            CHECK(least[c] >= 0.99 * 1.5);
        }
    }
}
