// The contrast lever and S_material (docs/design.md, "Contrast"): the
// spread measure against images of known spread, and a round trip in which a
// known volume at a known (k_s, contrast) renders the "photo" and the fit
// started from (0, 1) gives both back.

#include "jade/core/display.h"
#include "jade/core/random.h"
#include "jade/fit/appearance.h"
#include "jade/fit/display.h"
#include "jade/fit/fit_session.h"
#include "jade/geometry/mesh.h"
#include "jade/geometry/mesh_accel.h"
#include "jade/render/media/grid.h"
#include "support/fit_test_scene.h"

#include <catch2/catch.hpp>

#include <sstream>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

using namespace jade;

namespace {

// The population spread of a set of values.
double spread_of(const std::vector<double>& v) {
    double s = 0, s2 = 0;
    for (double x : v) s += x, s2 += x * x;
    const double m = s / v.size();
    return std::sqrt(s2 / v.size() - m * m);
}

// A film whose every pixel holds `value(x, y)` exactly (two equal samples: no variance).
template <class F>
Film exact_film(int w, int h, F value) {
    Film f(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int i = 0; i < 2; ++i) f.add_sample(x, y, value(x, y), true);
    return f;
}

// A render of known material under known shading: a ramp from 0.2 to 1
// across the image times stripes of two albedos, and its shading render
// (the stripes' mean albedo under the same ramp).
struct ShadedStripes {
    // `ramps`: instead of two levels, a sawtooth across 240 rows, whose
    // histogram is smooth and which blocks of a few rows leave as it is.
    explicit ShadedStripes(int width = 40, int height = 30, bool ramps = false)
        : w(width), h(height), ramps(ramps) {}
    int w, h;
    bool ramps;
    double shade(int x) const { return 0.2 + 0.8 * x / (w - 1.0); }
    double stripe(int y) const { return ramps ? 0.25 + 0.2 * (y % 240) / 239.0 : (y / 3) % 2 ? 0.25 : 0.45; }
    Film shading = exact_film(w, h, [this](int x, int) { return Spectrum(float(shade(x) * 0.35)); });
    Film render = exact_film(w, h, [this](int x, int y) { return Spectrum(float(shade(x) * stripe(y))); });

    // The render with `samples` samples a pixel, each its value × draw(rng):
    // a noise of mean 1 whose law the test chooses.
    template <class Draw>
    Film noisy_render(int samples, std::uint64_t seed, Draw draw) const {
        SplitMix64 rng(seed);
        Film f(w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int i = 0; i < samples; ++i)
                    f.add_sample(x, y, Spectrum(float(shade(x) * stripe(y) * draw(rng))), true);
        return f;
    }

    // The flattened render's levels: stripe × c, with c such that their mean
    // level is the render's (found by bisection, as the flattening does).
    std::vector<double> flat_levels() const {
        double target = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) target += 255.0 * srgb_encode(shade(x) * stripe(y)) / (w * h);
        auto levels_at = [this](double scale) {
            std::vector<double> levels;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) levels.push_back(255.0 * srgb_encode(stripe(y) * scale));
            return levels;
        };
        double lo = 0.0, hi = 2.0;
        for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (lo + hi);
            const auto l = levels_at(mid);
            (std::accumulate(l.begin(), l.end(), 0.0) / l.size() < target ? lo : hi) = mid;
        }
        return levels_at(0.5 * (lo + hi));
    }

    // Those levels as the photo: the stone with no shading and no noise.
    Photo flat_photo() const {
        Photo photo;
        photo.width = w;
        photo.height = h;
        for (double level : flat_levels()) {
            const auto l = std::uint8_t(std::lround(level));
            photo.levels.push_back({l, l, l});
            photo.foreground.push_back(1);
        }
        return photo;
    }
};

// The "photo" of a round trip: `volume` rendered at (k, g) in the test
// scene, flattened by its shading render, as a flat scan would show the
// material (fitting renders' size and exposure from `make`). Its seed is
// not the fit's, so the fit does not find the photo's own noise again.
Photo flat_photo(const test::FitTestScene& t, const MaterialVolume& volume, const FitOptions& make,
                 const std::array<double, 3>& k, const std::array<double, 3>& g, int spp) {
    const Photo dummy = test::ramp_photo(40, 190, 20);
    RenderSettings photo_settings;
    photo_settings.seed = test::kPhotoSeed;
    const FitSession maker(volume, t.scene, t.camera, photo_settings, dummy, make);
    return flat_render(maker.render_at(k, g, spp).film, maker.render_at(k, {0, 0, 0}, spp).film, make.exposure);
}


// A fit from k_s 0 and contrast 1 (64 spp, 32 renders) of the test
// scene's volume toward a "photo" of it at `denser` times its density
// scale and contrast 4 (k_s 0.5, 0.3, 0.1): the stops for the sharper
// stone (FitOptions::stop_at_density_ceiling, stop_at_first_rise).
struct DenserPhotoFit {
    test::FitTestScene t{test::ramp_photo(40, 190, 20), 32};
    RenderSettings settings;
    double start = t.volume.optics.density_scale;
    FitOptions options;
    Photo photo;
    explicit DenserPhotoFit(double denser) {
        MaterialVolume dense = t.volume;
        dense.optics.density_scale = denser * start;
        options.width = t.camera.width;
        options.exposure = 4.f;
        photo = flat_photo(t, dense, options, {0.5, 0.3, 0.1}, {4.0, 4.0, 4.0}, 512);
        options.ks_start = std::array<double, 3>{0.0, 0.0, 0.0};
        options.contrast_start = std::array<double, 3>{1.0, 1.0, 1.0};
        options.spp = 64;
        options.max_renders = 32;
    }
    FitOutcome run(const FitOptions& o) const {
        return FitSession(t.volume, t.scene, t.camera, settings, photo, o).run();
    }
};

}  // namespace

TEST_CASE("material spread: the shading divides out, the material's spread stays", "[fitter][contrast]") {
    const ShadedStripes scene;
    // Exact films: both halves of a render are the same, and hold no noise.
    const SplitFilms shading{scene.shading, scene.shading}, render{scene.render, scene.render};
    // Against the same medium the material adds nothing.
    const MaterialSpread none = material_spread(shading, shading, 1.f, 1);
    for (int c = 0; c < 3; ++c) CHECK(none.s[c] == Approx(0.0).margin(1e-3));  // float rounding of the ratio

    const std::vector<double> levels = scene.flat_levels();
    const MaterialSpread s = material_spread(render, shading, 1.f, 1);
    for (int c = 0; c < 3; ++c) {
        CHECK(s.s[c] == Approx(spread_of(levels)).epsilon(1e-4));
        CHECK(s.noise[c] == 0.0);
    }
    // The whole render's spread is far larger: the ramp counts there.
    const DisplayStatistics whole = display_statistics(scene.render, 1.f);
    CHECK(whole.s[0] > 1.5 * s.s[0]);
}

TEST_CASE("material spread: the noise of heavy-tailed samples is taken out", "[fitter][contrast]") {
    // The stripes under the ramp again, but every sample of the render is
    // its pixel's value × X, X = 4 with probability 1/4 and 0 otherwise
    // (mean 1, the light's rare paths in miniature): 64 samples a half give
    // each pixel of a half a relative error of √3/8 ≈ 0.22, about 13
    // levels, against the stripes' spread of about 16.6. The shading render
    // is exact.
    const ShadedStripes scene;
    constexpr int kPerHalf = 64;
    auto noisy_half = [&](std::uint64_t seed) {
        return scene.noisy_render(kPerHalf, seed, [](SplitMix64& rng) { return rng.uniform() < 0.25 ? 4.0 : 0.0; });
    };
    const SplitFilms shading{scene.shading, scene.shading};
    // Seeds far apart: a SplitMix64 stream is its seed counted up.
    const SplitFilms render{noisy_half(1), noisy_half(std::uint64_t(1) << 40)};
    const double truth = spread_of(scene.flat_levels());
    const MaterialSpread s = material_spread(render, shading, 1.f, 1);
    // The whole render's spread before the noise is taken out.
    const double raw = std::sqrt(s.s[0] * s.s[0] + s.noise[0] * s.noise[0]);
    INFO("truth " << truth << ", estimate " << s.s[0] << ", noise " << s.noise[0] << ", raw " << raw);
    CHECK(s.noise[0] > 6.0);
    CHECK(raw > truth + 1.5);
    // The estimate is the covariance of the halves' levels over the 1200
    // pixels; its variance, (2·σ_T²·σ_h² + σ_h⁴)/n with σ_T ≈ 16.6 and
    // σ_h ≈ 13, makes S²'s standard error about 10 and S's about 0.3 (12
    // seeds gave 16.58 ± 0.26). The sRGB curve's concavity at a half's noise
    // lowers both stripes' levels by about 1 % alike, 0.2 levels of S.
    // 1.2 levels is four standard errors.
    for (int c = 0; c < 3; ++c) CHECK(s.s[c] == Approx(truth).margin(1.2));
}

TEST_CASE("material spread: the noise's bias is extrapolated away from halves and quarters", "[fitter][contrast]") {
    // The stripes under the ramp on 200 × 150 pixels, every sample its
    // pixel's value × X, X exponential (mean 1, standard deviation 1: a
    // skewed, smooth noise), 2 samples a quarter. The sRGB curve bends the
    // noisy means' levels, so the halves' covariance reads low by a bias
    // that falls as 1/n; the quarters' covariance, at half the samples,
    // reads twice as low, and 2·Cov(halves) − Cov(quarters) cancels it.
    const ShadedStripes scene(200, 150);
    constexpr int kPerQuarter = 2;
    auto noisy_quarter = [&](std::uint64_t seed) {
        return scene.noisy_render(kPerQuarter, seed, [](SplitMix64& rng) { return -std::log(1.0 - rng.uniform()); });
    };
    const ImageF32 flat{scene.w, scene.h, 4, scene.shading.rgba(true)};
    const SplitFilms shading_halves{scene.shading, scene.shading, {}};
    SplitFilms shading = shading_halves;
    shading.quarters = {flat, flat, flat, flat};
    // Eight renders: the mean of each estimate has a standard error of
    // 0.05 (halves) and 0.07 (extrapolated) levels; one render's are 0.15
    // and 0.21 (40 renders: 16.08 ± 0.15 and 16.57 ± 0.21 against 16.59).
    constexpr int kRenders = 8;
    double halves_mean = 0.0, extrapolated_mean = 0.0;
    for (std::uint64_t r = 1; r <= kRenders; ++r) {
        std::vector<Film> q;
        // Seeds far apart: a SplitMix64 stream is its seed counted up.
        for (std::uint64_t i = 0; i < 4; ++i) q.push_back(noisy_quarter((r << 44) + (i << 40)));
        SplitFilms render{q[0], q[2], {}};
        render.first.merge(q[1]);
        render.second.merge(q[3]);
        halves_mean += material_spread(render, shading_halves, 1.f, 1).s[0] / kRenders;
        for (const Film& f : q) render.quarters.push_back(ImageF32{f.width(), f.height(), 4, f.rgba(true)});
        extrapolated_mean += material_spread(render, shading, 1.f, 1).s[0] / kRenders;
    }
    const double truth = spread_of(scene.flat_levels());
    INFO("truth " << truth << ", from halves " << halves_mean << ", extrapolated " << extrapolated_mean);
    // Halves alone: 0.5 levels low, well beyond their standard error.
    CHECK(halves_mean < truth - 0.3);
    // Extrapolated: within 3.5 standard errors of the truth.
    CHECK(extrapolated_mean == Approx(truth).margin(0.25));
}

TEST_CASE("material spread: how far S² scatters between renders, read from one render's quarters",
          "[fitter][contrast]") {
    // The same stripes and noise, 16 independent renders in quarters. Each
    // render's MaterialSpread::scatter (the standard deviation of its six
    // quarter pairs' covariances) is an estimate, from that render alone, of
    // how far its S² lies from the next render's; the standard deviation of
    // S² over the 16 renders measures it. With 16 renders that deviation is
    // itself known to about 18 %, and one render's six pairs to about 30 %
    // (their mean over 16 to 8 %): a factor of 1.6 either way is three
    // standard errors of the ratio.
    const ShadedStripes scene(200, 150);
    constexpr int kPerQuarter = 2;
    auto noisy_quarter = [&](std::uint64_t seed) {
        return scene.noisy_render(kPerQuarter, seed, [](SplitMix64& rng) { return -std::log(1.0 - rng.uniform()); });
    };
    const ImageF32 flat{scene.w, scene.h, 4, scene.shading.rgba(true)};
    SplitFilms shading{scene.shading, scene.shading, {flat, flat, flat, flat}};
    constexpr int kRenders = 16;
    std::vector<double> s2;
    double scatter_mean = 0.0;
    for (std::uint64_t r = 1; r <= kRenders; ++r) {
        std::vector<Film> q;
        // Seeds far apart: a SplitMix64 stream is its seed counted up.
        for (std::uint64_t i = 0; i < 4; ++i) q.push_back(noisy_quarter((r << 44) + (i << 40) + 7));
        SplitFilms render{q[0], q[2], {}};
        render.first.merge(q[1]);
        render.second.merge(q[3]);
        for (const Film& f : q) render.quarters.push_back(ImageF32{f.width(), f.height(), 4, f.rgba(true)});
        const MaterialSpread m = material_spread(render, shading, 1.f, 1);
        s2.push_back(m.s[0] * m.s[0]);
        scatter_mean += m.scatter[0] / kRenders;
    }
    double mean = 0.0, var = 0.0;
    for (double v : s2) mean += v / kRenders;
    for (double v : s2) var += (v - mean) * (v - mean) / (kRenders - 1);
    const double measured = std::sqrt(var);
    INFO("S² over the renders: " << mean << " ± " << measured << "; read from the quarters: " << scatter_mean);
    CHECK(scatter_mean > measured / 1.6);
    CHECK(scatter_mean < measured * 1.6);
    // Without quarters there is nothing to read it from.
    SplitFilms halves_only{noisy_quarter(1), noisy_quarter(2), {}};
    CHECK(material_spread(halves_only, {scene.shading, scene.shading, {}}, 1.f, 1).scatter[0] == 0.0);
}

TEST_CASE("read spread: the fit's first steps that showed S, and those whose search followed the noise",
          "[fitter][contrast]") {
    // Red's first step in five measured fits (noise, S, S²'s scatter; the
    // photo's spread over the fit's blocks). The demo's and Marble01's
    // searches held S, as did the bunny's under Marble021 at 64 spp (S² at
    // 0.15 of the photo's S²); at 16 spp the bunny's noise hides S (its
    // scatter was not measured: 0 here, the noise alone decides), and on the
    // vase the noise passes (4.29 against 4.30) but S² scatters by 0.38 of
    // the photo's S², and green's S read 0 to 6.4 levels from step to step.
    const double kTolerance = FitOptions{}.s_tolerance;
    struct Case {
        const char* name;
        double noise, s, scatter, photo;
        bool quiet, steady;
    };
    const Case cases[] = {{"demo, vase, 2 px", 15.25, 0.0, 5.12, 12.65, true, true},
                          {"Marble01, vase, 3 px", 11.31, 3.79, 1.77, 6.30, true, true},
                          {"Marble021, bunny, 8 px", 4.7, 0.0, 0.0, 1.7, false, true},
                          {"Marble021, vase, 6 px", 4.29, 0.0, 1.76, 2.15, true, false},
                          {"Marble021, bunny, 64 spp, 7 px", 3.48, 1.86, 0.54, 1.84, true, true}};
    for (const Case& k : cases) {
        INFO(k.name);
        MaterialSpread m;
        m.noise[0] = k.noise;
        m.s[0] = k.s;
        m.scatter[0] = k.scatter;
        const SpreadReading r = read_spread(m, {k.photo, 0.0, 0.0}, 0, kTolerance);
        CHECK(r.quiet == k.quiet);
        CHECK(r.steady == k.steady);
        CHECK(r.readable() == (k.quiet && k.steady));
    }
    // A flat photo on a flat volume: nothing spreads, and S²'s scatter is
    // rounding; it is read (S 0 against 0), not refused. Spreads under the
    // S tolerance are read as if at it: a one-colour dark photo (levels 6,
    // 5, 4) on the cow at full size had 0.02 levels of noise over 8-px
    // blocks, more than twice its spread of 0, and was called hidden.
    MaterialSpread flat;
    flat.scatter[0] = 1e-9;
    CHECK(read_spread(flat, {0.0, 0.0, 0.0}, 0, kTolerance).readable());
    flat.noise[0] = 0.02;
    CHECK(read_spread(flat, {0.0, 0.0, 0.0}, 0, kTolerance).readable());
    // Within the tolerance's limits (noise 2 × 1.5, S² scatter 0.2 × 1.5²)
    // and beyond them.
    flat.noise[0] = 2.9;
    flat.scatter[0] = 0.44;
    CHECK(read_spread(flat, {0.5, 0.0, 0.0}, 0, kTolerance).readable());
    flat.noise[0] = 3.1;
    CHECK_FALSE(read_spread(flat, {0.5, 0.0, 0.0}, 0, kTolerance).quiet);
    flat.noise[0] = 2.9;
    flat.scatter[0] = 0.46;
    CHECK_FALSE(read_spread(flat, {0.5, 0.0, 0.0}, 0, kTolerance).steady);
    // The render's own S counts where it is the larger.
    MaterialSpread m;
    m.noise[0] = 3.9;
    m.s[0] = 2.0;
    m.scatter[0] = 0.5;
    CHECK(read_spread(m, {1.0, 0.0, 0.0}, 0, kTolerance).readable());
    m.s[0] = 1.0;
    CHECK_FALSE(read_spread(m, {1.0, 0.0, 0.0}, 0, kTolerance).readable());
}

TEST_CASE("material D: the shading divides out of the histogram distance", "[fitter][contrast]") {
    const ShadedStripes scene;
    const int w = scene.w, h = scene.h;
    // The photo: the stripes alone, at the flattened render's two levels.
    const std::vector<double> flat = scene.flat_levels();
    Photo photo;
    photo.width = w;
    photo.height = h;
    for (double level : flat) {
        const auto l = std::uint8_t(std::lround(level));
        photo.levels.push_back({l, l, l});
        photo.foreground.push_back(1);
    }
    // One render pixel per photo pixel; exact films (both halves the same,
    // no noise): blocks of one pixel.
    const SplitFilms render{scene.render, scene.render}, shading{scene.shading, scene.shading};
    const MaterialAppearance m = compare_material(photo, render, shading, 1.f, double(w));
    CHECK(m.block == 1);
    CHECK(m.blocks == std::size_t(w * h));
    const RgbHistogram photo_hist = RgbHistogram::of(photo.levels);
    const DisplayStatistics whole = display_statistics(scene.render, 1.f);
    for (int c = 0; c < 3; ++c) {
        // A level off by one in float rounding of the ratio moves at most a
        // few pixels' share between neighbouring bins.
        CHECK(m.d[c] < 1e-3);
        CHECK(m.s_material[c] == Approx(m.s_photo[c]).margin(0.5));
        // The whole render's histogram carries the ramp: far from the photo's.
        CHECK(histogram_distance(whole.histogram, photo_hist, c) > 0.1);
    }
    // The same stripes at the same scale: the same structure.
    CHECK(m.structure == Approx(0.0).margin(0.05));
    // A photo of twice the stripes' contrast in levels is far from the material.
    Photo wider = photo;
    const double mean = std::accumulate(flat.begin(), flat.end(), 0.0) / flat.size();
    for (std::size_t i = 0; i < flat.size(); ++i) {
        const auto l = std::uint8_t(std::clamp(std::lround(mean + 2 * (flat[i] - mean)), 0L, 255L));
        wider.levels[i] = {l, l, l};
    }
    const MaterialAppearance far = compare_material(wider, render, shading, 1.f, double(w));
    for (int c = 0; c < 3; ++c) CHECK(far.d[c] > 0.5);
}

TEST_CASE("material D: read over blocks where the render's noise is small beside the photo's spread",
          "[fitter][contrast]") {
    // A sawtooth of levels under the ramp, the photo its flat levels; the
    // render's two halves with 8 samples a pixel each, every sample its
    // pixel's value × X, X exponential. Over one pixel the noise spreads the
    // levels as much as the stone does; D is read over the smallest blocks
    // where its spread is at most a quarter of the photo's there, and comes
    // nearer the exact render's D over those blocks than one pixel's D does
    // to one pixel's.
    const ShadedStripes scene(240, 240, true);  // square: the photo spans its larger side
    const Photo photo = scene.flat_photo();
    const SplitFilms shading{scene.shading, scene.shading, {}};
    const double side = double(scene.w);
    const MaterialAppearance exact = compare_material(photo, {scene.render, scene.render, {}}, shading, 1.f, side);
    CHECK(exact.d_block == 1);  // no noise: one pixel's blocks
    auto exponential = [](SplitMix64& rng) { return -std::log(1.0 - rng.uniform()); };
    const SplitFilms noisy{scene.noisy_render(8, 1ull << 40, exponential),
                           scene.noisy_render(8, 2ull << 40, exponential), {}};
    const MaterialAppearance m = compare_material(photo, noisy, shading, 1.f, side);
    const int b = m.d_block;
    INFO("D over " << b << " px: " << m.d[0] << ", the exact render's " << exact.d_by_block[b - 1][0]
                   << "; over one pixel " << m.d_by_block[0][0] << " against " << exact.d_by_block[0][0]);
    REQUIRE(b > 1);
    REQUIRE(b < MaterialAppearance::kMaxBlock);
    // The rule: quiet enough at b, not at the block before.
    auto noise_share = [&](int block) {
        const double photo_spread = photo_block_histogram(photo, side / block).spread(0);
        return material_spread(noisy, shading, 1.f, block).noise[0] / photo_spread;
    };
    CHECK(noise_share(b) <= MaterialAppearance::kDNoiseShare);
    CHECK(m.d_noise[0] / m.d_photo_spread[0] == Approx(noise_share(b)));
    CHECK(noise_share(b - 1) > MaterialAppearance::kDNoiseShare);
    CHECK(noise_share(1) > 0.7);
    for (int c = 0; c < 3; ++c) {
        CHECK(m.d[c] == m.d_by_block[b - 1][c]);
        CHECK(std::abs(m.d[c] - exact.d_by_block[b - 1][c]) <
              0.7 * std::abs(m.d_by_block[0][c] - exact.d_by_block[0][c]));
    }
}

TEST_CASE("quiet block: the smallest block whose noise is that share of the photo's spread", "[fitter][contrast]") {
    // The same sawtooth and noise. quiet_block jumps ahead by the noise's
    // excess (noise as 1/block): it must never skip a quiet block.
    const ShadedStripes scene(240, 240, true);
    const Photo photo = scene.flat_photo();
    const SplitFilms shading{scene.shading, scene.shading, {}};
    auto exponential = [](SplitMix64& rng) { return -std::log(1.0 - rng.uniform()); };
    const SplitFilms noisy{scene.noisy_render(8, 1ull << 40, exponential),
                           scene.noisy_render(8, 2ull << 40, exponential), {}};
    const double side = double(scene.w);
    auto excess = [&](int block, double share) {
        const double photo_spread = photo_block_histogram(photo, side / block).spread(0);
        return material_spread(noisy, shading, 1.f, block).noise[0] / (share * photo_spread);
    };
    for (const double share : {1.0, 0.5, 0.25}) {
        INFO("share " << share);
        const QuietBlock q = quiet_block(photo, noisy, shading, 1.f, side, 1, share);
        INFO("block " << q.block);
        REQUIRE(q.quiet);
        CHECK(excess(q.block, share) <= 1.0);
        for (int b = 1; b < q.block; ++b) CHECK(excess(b, share) > 1.0);
        CHECK(q.spread.noise[0] == Approx(material_spread(noisy, shading, 1.f, q.block).noise[0]));
        CHECK(q.photo_spread[0] == Approx(photo_spread(photo, side / q.block)[0]));
    }
    // Starting above the smallest quiet block keeps the start.
    CHECK(quiet_block(photo, noisy, shading, 1.f, side, 7, 1.0).block == 7);
    // Too small a share for any block: the largest, not quiet.
    const QuietBlock none = quiet_block(photo, noisy, shading, 1.f, side, 1, 0.01);
    CHECK_FALSE(none.quiet);
    CHECK(none.block == kMaxMaterialBlock);
    // A noiseless render is quiet over one pixel.
    CHECK(quiet_block(photo, {scene.render, scene.render, {}}, shading, 1.f, side, 1, 0.25).block == 1);
}

TEST_CASE("samples for a noise: where the largest block is not quiet, the count named quiets it",
          "[fitter][contrast]") {
    // The sawtooth under exponential noise (variance per sample 1, so the
    // noise falls as 1/√samples) over the largest block, at 4 samples a
    // pixel, with a limit 1.7 times below its noise: spp_for_noise names 32
    // (4 × 1.7³ = 19.7, rounded up to a power of two), and a render with
    // that many samples has its noise under the limit, as 1/√samples says.
    // Each render's noise is read over 900 blocks (its relative scatter
    // about 3 %; the ratio's tolerance is 3 of its scatters).
    const ShadedStripes scene(240, 240, true);
    const SplitFilms shading{scene.shading, scene.shading, {}};
    auto exponential = [](SplitMix64& rng) { return -std::log(1.0 - rng.uniform()); };
    auto noise_at = [&](int samples) {
        const SplitFilms noisy{scene.noisy_render(samples / 2, 3ull << 40, exponential),
                               scene.noisy_render(samples / 2, 4ull << 40, exponential), {}};
        return material_spread(noisy, shading, 1.f, kMaxMaterialBlock).noise[0];
    };
    const double noise = noise_at(4), limit = noise / 1.7;
    const int spp = spp_for_noise(4, noise, limit);
    CHECK(spp == 32);
    const double quieter = noise_at(spp);
    INFO("noise " << noise << " at 4 samples, " << quieter << " at " << spp << "; limit " << limit);
    CHECK(quieter <= limit);
    CHECK(quieter == Approx(noise * std::sqrt(4.0 / spp)).epsilon(0.12));
    // Already quiet: the count it has; 1.26 times too loud: twice the count
    // (1.26³ = 2.0). A limit of 0 (a photo that spreads nothing): no count.
    CHECK(spp_for_noise(16, 1.0, 2.0) == 16);
    CHECK(spp_for_noise(16, 1.25, 1.0) == 32);
    CHECK(spp_for_noise(16, 1.0, 0.0) == 0);
    CHECK(spp_for_noise(16, 1e4, 1.0) == 0);
}

TEST_CASE("photo spread at a coarser scale averages the finer texture away", "[fitter][contrast]") {
    Photo p;
    p.width = p.height = 64;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const std::uint8_t l = ((x + y) % 2) ? 200 : 40;  // a one-pixel checkerboard
            p.levels.push_back({l, l, l});
        }
    p.foreground.assign(p.levels.size(), 1);
    const auto fine = photo_spread(p, 64.0);  // the photo's own scale: its histogram's spread
    CHECK(fine[0] == Approx(80.0));
    const auto coarse = photo_spread(p, 16.0);  // 4×4 blocks: every block the same
    CHECK(coarse[0] == Approx(0.0).margin(0.5));
}

TEST_CASE("material block: the side over which a render's noise averages to 0.1", "[fitter][contrast]") {
    CHECK(material_block(0.05) == 1);
    CHECK(material_block(0.4) == 4);
    CHECK(material_block(0.41) == 5);
    CHECK(material_block(3.0) == 8);
}

TEST_CASE("contrast fit: the first dS/dg, in proportion to g unless that would not reach the photo's S by the ceiling",
          "[fitter][contrast]") {
    // S = 6 at g = 1 against the photo's 14: 6·g reaches 14 by g = 2.3,
    // under the ceiling of 4, so S/g (times the clipping's elasticity) stands.
    CHECK(jade::first_spread_slope(6.0, 1.0, 1.0, 14.0) == Approx(6.0));
    CHECK(jade::first_spread_slope(12.0, 2.0, 0.8, 14.0) == Approx(4.8));
    // The sweep's demo, red, at g = 1: S 0.19 against the photo's 12.6 (a
    // stone washed out by k_s). 0.19·g would not reach 12.6 by g = 66; the
    // slope is the one that reaches it at the ceiling, 12.6 / 4, where the
    // next step measured about 3.2.
    CHECK(jade::first_spread_slope(0.19, 1.0, 1.0, 12.6) == Approx(12.6 / 4.0));
    // A flat material (S the rounding of one colour): the photo's S, at least 1.
    CHECK(jade::first_spread_slope(0.05, 1.0, 1.0, 0.3) == Approx(1.0));
    CHECK(jade::first_spread_slope(0.05, 1.0, 1.0, 6.0) == Approx(6.0));
}

TEST_CASE("contrast fit: where the contrast would clip many voxels, the density scale rises instead",
          "[fitter][contrast][fit-session]") {
    test::FitTestScene t(test::ramp_photo(40, 190, 20), 32);
    RenderSettings settings;
    // The "photo": the volume at 3× its density scale and contrast 3.5, so
    // that at its own density scale each channel's S needs a contrast above
    // the ceiling of 4 (the fit's first step, contrast 4, falls short).
    const double start = t.volume.optics.density_scale;
    MaterialVolume dense = t.volume;
    dense.optics.density_scale = 3.0 * start;
    const std::array<double, 3> k_true{0.5, 0.3, 0.1}, g_true{3.5, 3.5, 3.5};
    FitOptions make;
    make.width = t.camera.width;
    make.exposure = 4.f;
    const Photo photo = flat_photo(t, dense, make, k_true, g_true, 512);

    FitOptions options = make;
    options.ks_start = std::array<double, 3>{0.0, 0.0, 0.0};
    options.contrast_start = std::array<double, 3>{1.0, 1.0, 1.0};
    options.spp = 256;
    // Three steps of density scale, each judged by two more renders, besides
    // the brightness and contrast steps: with two versions of the renderer's
    // noise the fit took 24 and 26 renders, at or just past the default
    // budget of 24, so one noisy step decided the outcome. The test is of
    // where the fit goes, not of its budget.
    options.max_renders = 32;
    FitSession session(t.volume, t.scene, t.camera, settings, photo, options);
    const FitOutcome out = session.run();
    INFO("density scale " << out.density_scale << "; contrast " << out.contrast[0] << ", " << out.contrast[1] << ", "
                          << out.contrast[2] << " in " << out.records.size() << " renders; S " << out.s_material[0]
                          << ", " << out.s_material[1] << ", " << out.s_material[2] << " against " << out.s_photo[0]
                          << ", " << out.s_photo[1] << ", " << out.s_photo[2] << "; " << out.reason[0] << " "
                          << out.reason[1] << " " << out.reason[2]);
    REQUIRE(out.converged);
    CHECK(out.density_scale_start == start);
    CHECK(out.density_scale > 1.5 * start);
    CHECK(out.density_scale <= 8.0 * start);
    // Every record at the fitted density scale is one of the last steps.
    CHECK(out.records.back().density_scale == out.density_scale);
    CHECK(out.density_scale_max == 8.0 * start);

    // Started from that outcome (the sharper stone's fit, app/pipeline.h), a
    // fit of the same volume at the fitted density scale renders nothing at
    // the k_s bounds and no k_s search: its first step is at the outcome,
    // where A and S matched, so it converges there, under the same ceiling.
    CHECK(sharpening_for(out).amount == kSharperStone);
    MaterialVolume fitted = t.volume;
    fitted.optics.density_scale = out.density_scale;
    FitOptions again = make;
    again.start = start_from(out);
    again.max_renders = kMinContrastRenders;
    FitSession warm(fitted, t.scene, t.camera, settings, photo, again);
    const FitOutcome resumed = warm.run();
    INFO("started from the outcome: " << resumed.records.size() << " rows; " << resumed.reason[0] << " "
                                      << resumed.reason[1] << " " << resumed.reason[2]);
    CHECK(resumed.converged);
    const auto step = std::find_if(resumed.records.begin(), resumed.records.end(),
                                   [](const FitRecord& r) { return !r.shading; });
    REQUIRE(step != resumed.records.end());
    CHECK(step->ks == out.ks);
    CHECK(step->contrast == out.contrast);
    CHECK(resumed.exposure == out.exposure);
    CHECK(resumed.density_scale_start == out.density_scale);
    CHECK(resumed.density_scale_max == out.density_scale_max);
    CHECK(resumed.estimated_error == out.estimated_error);  // its blocks chosen as the first's were
    CHECK(resumed.renders <= 3);  // one step: a render and its shading (and a fitting-size row)

    // Held at its own density scale, the fit tries contrasts above the
    // ceiling, and above those fitted with the density scale (a few steps
    // show it). Its k_s search takes 3 renders and each contrast step 2:
    // given 11, it makes four steps, the last two past the ceiling (7.7 and
    // 11.8 measured; given 16, it went on to 16, the cap, and stopped).
    options.fit_density = false;
    options.max_renders = 11;
    FitSession held(t.volume, t.scene, t.camera, settings, photo, options);
    const FitOutcome kept = held.run();
    double most = 0.0;
    std::ostringstream tried;
    for (const FitRecord& r : kept.records) {
        CHECK(r.density_scale == start);
        most = std::max({most, r.contrast[0], r.contrast[1], r.contrast[2]});
        tried << " (" << r.contrast[0] << ", " << r.contrast[1] << ", " << r.contrast[2] << ")";
    }
    INFO("held at its density scale, contrasts tried:" << tried.str());
    CHECK(kept.density_scale == start);
    CHECK(most > 4.0);
    CHECK(most > *std::max_element(out.contrast.begin(), out.contrast.end()));
}

TEST_CASE("contrast fit: stopped where the density scale reaches its ceiling, the point it would render next kept",
          "[fitter][contrast][fit-session]") {
    // The "photo" is the volume at 32× its density scale and contrast 4,
    // beyond the fit's ceiling of 8×: the density scale rises to within a
    // step of that ceiling (at 16× and 3.5 the fit matched at 6.4×). Asked to stop
    // there (the pipeline's first fit, which the sharper stone's takes on
    // from there), the fit makes no render at the ceiling, says where it
    // would have rendered next, and asks for kDefaultSharpen; a fit not
    // asked to stop goes the same way to that point and renders it next.
    const DenserPhotoFit fit(32.0);
    const double start = fit.start;
    FitOptions options = fit.options;
    options.stop_at_density_ceiling = true;
    const FitOutcome stopped = fit.run(options);
    std::ostringstream path;
    for (const FitRecord& r : stopped.records) path << " " << r.density_scale;
    INFO("density scales rendered:" << path.str() << "; stopped at " << stopped.density_scale << " in "
                                    << stopped.renders << " renders; " << stopped.reason[0]);
    REQUIRE(stopped.stopped_at_density_ceiling);
    CHECK_FALSE(stopped.converged);
    // At the ceiling: no step of at least kMinDensityStep is left below it
    // (the last raise may end short of it: 80 → 149.1 of 160).
    CHECK(stopped.density_scale <= stopped.density_scale_max);
    CHECK(stopped.density_scale_max == 8.0 * start);
    CHECK(at_density_ceiling(stopped.density_scale, stopped.density_scale_max));
    for (const FitRecord& r : stopped.records) CHECK(r.density_scale < stopped.density_scale);
    for (int c = 0; c < 3; ++c) {
        CHECK(stopped.state[c] == ChannelState::Searching);
        CHECK_THAT(stopped.reason[c], Catch::Contains("ceiling"));
        CHECK(stopped.contrast[c] > 0.0);
        CHECK(stopped.contrast[c] <= kMaxContrast);
        CHECK(stopped.ks[c] >= stopped.limits.k_min[c]);
        CHECK(stopped.ks[c] <= stopped.limits.k_max);
    }
    CHECK(sharpening_for(stopped).amount == kDefaultSharpen);
    CHECK_THAT(sharpening_for(stopped).why, Catch::Contains("ceiling"));

    // Not asked to stop, with a budget of two steps more (a step in density
    // scale is taken only where two steps can judge it): the same renders,
    // then a step at the ceiling, at the point the stopped fit named.
    options.stop_at_density_ceiling = false;
    options.max_renders = stopped.renders + 4;
    const FitOutcome further = fit.run(options);
    REQUIRE(further.records.size() > stopped.records.size());
    for (std::size_t i = 0; i < stopped.records.size(); ++i) {
        CHECK(further.records[i].ks == stopped.records[i].ks);
        CHECK(further.records[i].contrast == stopped.records[i].contrast);
        CHECK(further.records[i].a_render == stopped.records[i].a_render);
    }
    // At this size a step's shading render is a row too, made first.
    REQUIRE(further.records.size() >= stopped.records.size() + 2);
    const FitRecord& shading = further.records[stopped.records.size()];
    const FitRecord& next = further.records[stopped.records.size() + 1];
    CHECK(shading.shading);
    CHECK(shading.ks == stopped.ks);
    CHECK_FALSE(next.shading);
    CHECK(next.density_scale == stopped.density_scale);
    CHECK(next.ks == stopped.ks);
    CHECK(next.contrast == stopped.contrast);
    CHECK_FALSE(further.stopped_at_density_ceiling);
}

TEST_CASE("contrast fit: stopped where the density scale's first rise meets the stone's need short of its ceiling",
          "[fitter][contrast][fit-session]") {
    // The "photo" is the volume at 1.5 times its density scale and contrast 4:
    // at its own density scale the contrast would pass the ceiling of 4,
    // and the rise the fit asks for is less than a step's most (4×). Asked
    // to stop there (the pipeline's first fit, which the stone sharpened by
    // kSharperStone takes on), the fit renders nothing at the new density
    // scale and names the point it would render next; a fit not asked to
    // stop goes the same way and renders that point next.
    const DenserPhotoFit fit(1.5);
    const double start = fit.start;
    FitOptions options = fit.options;
    options.stop_at_density_ceiling = options.stop_at_first_rise = true;
    const FitOutcome stopped = fit.run(options);
    std::ostringstream path;
    for (const FitRecord& r : stopped.records) path << " " << r.density_scale;
    INFO("density scales rendered:" << path.str() << "; stopped at " << stopped.density_scale << " in "
                                    << stopped.renders << " renders; " << stopped.reason[0]);
    REQUIRE(stopped.stopped_at_first_rise);
    CHECK_FALSE(stopped.stopped_at_density_ceiling);
    CHECK(stopped_for_sharper_stone(stopped));
    CHECK_FALSE(stopped.converged);
    // One rise, by less than a step's most, short of the ceiling; nothing
    // rendered after it.
    CHECK(stopped.density_scale > 1.1 * start);
    CHECK(stopped.density_scale < 4.0 * start);
    CHECK_FALSE(at_density_ceiling(stopped.density_scale, stopped.density_scale_max));
    for (const FitRecord& r : stopped.records) CHECK(r.density_scale == start);
    for (int c = 0; c < 3; ++c) {
        CHECK(stopped.state[c] == ChannelState::Searching);
        CHECK_THAT(stopped.reason[c], Catch::Contains("first rise"));
    }
    CHECK(sharpening_for(stopped).amount == kSharperStone);
    CHECK_THAT(sharpening_for(stopped).why, Catch::Contains("first rise"));

    // Not asked to stop at the first rise: the same renders, then a step at
    // the new density scale, at the point the stopped fit named.
    options.stop_at_first_rise = false;
    options.max_renders = stopped.renders + 4;
    const FitOutcome further = fit.run(options);
    REQUIRE(further.records.size() >= stopped.records.size() + 2);
    for (std::size_t i = 0; i < stopped.records.size(); ++i) {
        CHECK(further.records[i].ks == stopped.records[i].ks);
        CHECK(further.records[i].contrast == stopped.records[i].contrast);
    }
    const FitRecord& next = further.records[stopped.records.size() + 1];
    CHECK_FALSE(next.shading);
    CHECK(next.density_scale == stopped.density_scale);
    CHECK(next.ks == stopped.ks);
    CHECK(next.contrast == stopped.contrast);
    CHECK_FALSE(further.stopped_at_first_rise);
}

TEST_CASE("contrast fit: a render at a known k_s and contrast fitted from (0 1) at half its width gives both back",
          "[fitter][contrast][fit-session]") {
    // The "photo" is the volume at a known k_s and contrast, flattened, at
    // the final camera's 48². The fit renders A at 24² and S_material at
    // 48² (as many samples per image: 64 per pixel against 256); its target
    // is the photo's S over blocks of the final render's pixels, and the
    // fitted material, measured by the final measurement's own renders
    // (another seed), has the photo's spread there.
    test::FitTestScene t(test::ramp_photo(40, 190, 20), 48);
    RenderSettings settings;
    const std::array<double, 3> k_true{0.5, 0.3, 0.1}, g_true{2.5, 1.6, 3.2};
    FitOptions make;
    make.width = t.camera.width;
    make.exposure = 4.f;
    const Photo photo = flat_photo(t, t.volume, make, k_true, g_true, 512);

    FitOptions options = make;
    options.width = 24;
    options.ks_start = std::array<double, 3>{0.0, 0.0, 0.0};
    options.contrast_start = std::array<double, 3>{1.0, 1.0, 1.0};
    options.spp = 256;
    FitSession session(t.volume, t.scene, t.camera, settings, photo, options);
    const FitOutcome out = session.run();
    INFO("k_s " << out.ks[0] << ", " << out.ks[1] << ", " << out.ks[2] << "; contrast " << out.contrast[0] << ", "
                << out.contrast[1] << ", " << out.contrast[2] << " in " << out.renders << " renders; S "
                << out.s_material[0] << ", " << out.s_material[1] << ", " << out.s_material[2] << " against "
                << out.s_photo[0] << ", " << out.s_photo[1] << ", " << out.s_photo[2] << " in "
                << out.material_block << " px blocks; " << out.reason[0] << out.reason[1] << out.reason[2]);
    REQUIRE(out.converged);
    CHECK(out.width == 24);
    CHECK(out.renders <= options.max_renders);
    // Two renders at 48² a step are counted, and are not rows of fit.csv;
    // the steps' rows are their volume renders box-downsampled to 24²
    // (48² is twice 24² in both sides), at 4 × 64 samples per pixel: rows
    // without a render of their own.
    int rendered_rows = 0, downsampled_rows = 0;
    for (const FitRecord& r : out.records) {
        CHECK_FALSE(r.shading);
        if (r.from_final_size) {
            ++downsampled_rows;
            CHECK(r.spp == 256);
            CHECK(r.a_final_size[0] >= 0.0);
        } else {
            ++rendered_rows;
        }
    }
    // Every step made a row of its own but the first where it stood at a
    // k_s render's (k_s, g): that row serves.
    CHECK(downsampled_rows >= 1);
    const int at_final_size = out.renders - rendered_rows;
    CHECK(at_final_size % 2 == 0);
    CHECK((at_final_size / 2 == downsampled_rows || at_final_size / 2 == downsampled_rows + 1));
    const double final_pixels_per_side = render_pixels_per_side(t.camera, t.volume.cube);
    const std::array<double, 3> target = photo_spread(photo, final_pixels_per_side / out.material_block);
    for (int c = 0; c < 3; ++c) CHECK(out.s_photo[c] == target[c]);

    // A at 48² is not A at 24² (sRGB is concave): k_s as the brightness
    // check at the final size leaves it, as the pipeline does.
    const FitSession::FinalBrightness check = session.final_brightness(64);
    // The final measurement at 48²: the fitted volume and its mean medium in
    // two halves each, at the photo's exposure.
    OpticalParams fitted = t.volume.optics;
    fitted.ks = check.ks;
    fitted.contrast = out.contrast;
    fitted.density_scale = out.density_scale;
    OpticalParams mean_medium = fitted;
    mean_medium.contrast = {0.0, 0.0, 0.0};
    const MaterialVolumeMedium material(t.volume, t.volume.cube, fitted);
    const MaterialVolumeMedium shading(t.volume, t.volume.cube, mean_medium, material.majorant());
    RenderSettings measure;
    measure.spp = 256;
    measure.seed = 7;
    Scene scene = t.scene;
    scene.medium = &material;
    const SplitFilms r = render_halves(scene, PinholeCamera(t.camera), measure);
    scene.medium = &shading;
    const SplitFilms s = render_halves(scene, PinholeCamera(t.camera), measure);
    const MaterialAppearance m = compare_material(photo, r, s, make.exposure, final_pixels_per_side);
    // The check took A at 48² from the fit's own renders there (64 spp in
    // halves, extrapolated), and foresaw ΔA at the fitted k_s as a 48²
    // render of 256 spp (another seed) has it. Like the fitting renders,
    // that render leaves the backdrop out (it measures the object alone: at
    // 48² the edge pixels the backdrop would bleed into raise A by 0.7).
    CHECK(check.from_fit);
    CHECK(check.spp == 64);
    CHECK(check.renders <= 3);
    OpticalParams at_fit = fitted;
    at_fit.ks = out.ks;
    const MaterialVolumeMedium unchecked(t.volume, t.volume.cube, at_fit);
    scene.medium = &unchecked;
    RenderSettings object_only = measure;
    object_only.backdrop.transparent = true;
    const DisplayStatistics full =
        display_statistics(render(scene, PinholeCamera(t.camera), object_only).film, make.exposure);
    const RgbHistogram photo_histogram = RgbHistogram::of(photo.foreground_levels());
    INFO("k_s after the brightness check " << check.ks[0] << ", " << check.ks[1] << ", " << check.ks[2]
                                           << "; measured at 48²: S " << m.s_material[0] << ", " << m.s_material[1] << ", " << m.s_material[2]
                               << " against the photo's " << m.s_photo[0] << ", " << m.s_photo[1] << ", "
                               << m.s_photo[2] << " in " << m.block << " px blocks");
    for (int c = 0; c < 3; ++c) {
        const double delta_full = full.a[c] - photo_histogram.mean(c);
        INFO("channel " << c << ": size change " << check.size_change[c] << ", dA expected " << check.delta[c]
                        << ", at 48² and 256 spp " << delta_full << " +- " << full.a_sigma[c]);
        // Twice the render's standard error (0.08–0.15 levels) and what the
        // extrapolation leaves (0.2–0.3; equal samples per pixel at both
        // sizes, 64, left 0.3–1.3 here).
        CHECK(std::abs(check.delta[c] - delta_full) < 2.0 * full.a_sigma[c] + 0.3);
        // The fit's tolerance of 1.5 levels, and the two measurements' own
        // scatter (covariances of two halves over about 850 blocks).
        CHECK(std::abs(m.s_material[c] - m.s_photo[c]) < options.s_tolerance + 1.0);
        CHECK(std::abs(out.contrast[c] - g_true[c]) < 0.2 * g_true[c]);
        CHECK(std::abs(check.ks[c] - k_true[c]) < 0.15);
    }
}

TEST_CASE("contrast fit: where the renders' noise hides S_material, the contrast stays and k_s matches A",
          "[fitter][contrast][fit-session]") {
    // A photo of one colour (S 0) and a volume at a small contrast (S_material
    // a fraction of a level), rendered at 4 samples per pixel at 24² and 48²:
    // the noise over the largest blocks is many times both spreads, so S
    // cannot be told from it. The contrast must stay where it started, the
    // fit says so per channel, and k_s still brings A to the photo's.
    test::FitTestScene t(test::ramp_photo(40, 190, 20), 48);
    Photo photo;
    photo.width = photo.height = 32;
    photo.levels.assign(32 * 32, Rgb8{150, 120, 100});
    photo.foreground.assign(photo.levels.size(), 1);
    FitOptions options;
    options.width = 24;
    options.spp = 16;  // 4 a pixel at 48²: kMinSpreadSpp's 16 is the floor there
    options.ks_start = std::array<double, 3>{0.0, 0.0, 0.0};
    const std::array<double, 3> g_start{0.05, 0.05, 0.05};
    options.contrast_start = g_start;
    RenderSettings settings;
    FitSession session(t.volume, t.scene, t.camera, settings, photo, options);
    const FitOutcome out = session.run();
    std::string warnings;
    for (const std::string& w : out.warnings) warnings += w + "\n";
    INFO("k_s " << out.ks[0] << ", " << out.ks[1] << ", " << out.ks[2] << "; contrast " << out.contrast[0] << ", "
                << out.contrast[1] << ", " << out.contrast[2] << " in " << out.renders << " renders over "
                << out.material_block << " px blocks\n"
                << warnings << out.reason[0] << out.reason[1] << out.reason[2]);
    REQUIRE(out.warnings.size() == 3);
    for (int c = 0; c < 3; ++c) {
        CHECK_FALSE(out.contrast_fitted[c]);
        CHECK(out.contrast[c] == g_start[c]);
        CHECK_THAT(out.warnings[c], Catch::Contains("the contrast was not fitted") &&
                                        Catch::Contains(channel_name(c)));
    }
    CHECK(out.material_block == kMaxMaterialBlock);
    CHECK(out.spread_spp == kMinSpreadSpp);
    // The count the summary names is the largest a channel's warning names
    // (none where no count would do).
    int named = 0;
    for (const std::string& w : out.warnings)
        if (const auto at = w.find("--fit-spread-spp "); at != std::string::npos)
            named = std::max(named, std::stoi(w.substr(at + 17)));
    CHECK(out.spread_spp_advised == named);
    CHECK(out.density_scale == t.volume.optics.density_scale);
    // A matched where the steps judged it (at 48², extrapolated from
    // halves): each channel at the first step that stood at its fitted k_s
    // (a later step for another channel moves it a little: the channels'
    // paths share their tentative collisions).
    REQUIRE(out.converged);
    for (int c = 0; c < 3; ++c) {
        const auto judged = std::find_if(out.records.begin(), out.records.end(), [&](const FitRecord& r) {
            return r.ks[c] == out.ks[c] && r.contrast[c] == out.contrast[c] && r.a_final_size[c] >= 0.0;
        });
        REQUIRE(judged != out.records.end());
        CHECK(std::abs(judged->a_final_size[c] - judged->a_photo[c]) < out.limits.tolerance);
    }
}

TEST_CASE("contrast fit: where the first step's noise hides S_material and more samples would show it, the fit "
          "takes them",
          "[fitter][contrast][fit-session]") {
    // The scene of the test above, and a photo of four patches 22 levels
    // apart in every channel: S is 11 levels over any block inside a patch.
    // At 16 samples per pixel (the floor at 48²) the first step's noise
    // hides a channel's S and names a count within kMaxSpreadSppGain times:
    // with --fit-spread-spp 0 the fit takes kMaxSpreadSppGain times the
    // samples and fits every channel's contrast; given as 16, the count
    // stays and the warning names the count. Whether the first step hides S
    // and which count it names are the noise's draw: over render seeds 1–8
    // red's S² scattered by 32–54 levels² between the first step's renders
    // where it hid (twice it did not hide), and the rule names a count
    // within reach for a scatter between 0.2 × 11² = 24 levels² and
    // 4^(2/3) times that, 61. Another machine draws otherwise at the same
    // seed (at 16 levels apart and seed 1 one machine named 64, another
    // 128, out of reach; the renders are bit-identical across thread
    // counts, not across processors and builds): the test takes the
    // first seed that shows the case, so that it checks what the fit does
    // with a hidden spread, not one draw. (One draw in eight here, seed 7,
    // hid red's S within reach but the raised fit then ran out of its 24
    // renders; a machine whose first such seed draws that would fail on
    // `converged`.)
    test::FitTestScene t(test::ramp_photo(40, 190, 20), 48);
    constexpr int kHalfStep = 11;
    Photo photo;
    photo.width = photo.height = 32;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const int d = ((x < 16) == (y < 16)) ? kHalfStep : -kHalfStep;
            photo.levels.push_back(Rgb8{std::uint8_t(150 + d), std::uint8_t(120 + d), std::uint8_t(100 + d)});
        }
    photo.foreground.assign(photo.levels.size(), 1);
    FitOptions options;
    options.width = 24;
    options.spp = 16;
    options.ks_start = std::array<double, 3>{0.0, 0.0, 0.0};
    options.contrast_start = std::array<double, 3>{0.05, 0.05, 0.05};
    RenderSettings settings;
    const auto fit = [&](int spread_spp) {
        FitOptions o = options;
        o.spread_spp = spread_spp;
        FitSession session(t.volume, t.scene, t.camera, settings, photo, o);
        return session.run();
    };
    const auto describe = [](const FitOutcome& out) {
        std::ostringstream s;
        s << "contrast " << out.contrast[0] << ", " << out.contrast[1] << ", " << out.contrast[2] << " in "
          << out.renders << " renders; S " << out.s_material[0] << ", " << out.s_material[1] << ", "
          << out.s_material[2] << " against " << out.s_photo[0] << ", " << out.s_photo[1] << ", " << out.s_photo[2]
          << " in " << out.material_block << " px blocks at " << out.spread_spp << " spp (raised from "
          << out.spread_spp_raised_from << ", advised " << out.spread_spp_advised << ")\n";
        for (const std::string& w : out.warnings) s << w << "\n";
        return s.str();
    };
    const auto hidden_within_reach = [](const FitOutcome& out) {
        return out.contrast_fitted != std::array<bool, 3>{true, true, true} &&
               out.spread_spp_advised > kMinSpreadSpp && out.spread_spp_advised <= kMaxSpreadSppGain * kMinSpreadSpp;
    };
    constexpr std::uint64_t kSeeds = 8;
    FitOutcome given;
    std::ostringstream tried;
    for (settings.seed = 1; settings.seed <= kSeeds; ++settings.seed) {
        given = fit(kMinSpreadSpp);
        if (hidden_within_reach(given)) break;
        tried << "seed " << settings.seed << ": " << describe(given);
    }
    INFO(tried.str());
    REQUIRE(settings.seed <= kSeeds);
    const FitOutcome raised = fit(0);
    INFO("seed " << settings.seed << "; given: " << describe(given) << "raised: " << describe(raised));

    CHECK(given.spread_spp == kMinSpreadSpp);
    CHECK(given.spread_spp_raised_from == 0);
    REQUIRE_FALSE(given.warnings.empty());
    CHECK_THAT(given.warnings[0], Catch::Contains("--fit-spread-spp " + std::to_string(given.spread_spp_advised) +
                                                  " would show it"));

    CHECK(raised.spread_spp_raised_from == kMinSpreadSpp);
    CHECK(raised.spread_spp == kMaxSpreadSppGain * kMinSpreadSpp);
    CHECK(raised.spread_spp_advised == 0);
    for (const std::string& w : raised.warnings) CHECK_THAT(w, !Catch::Contains("the contrast was not fitted"));
    REQUIRE(raised.converged);
    // The photo's S at the fit's blocks: 8 levels, less where a block
    // straddles two patches.
    for (int c = 0; c < 3; ++c) {
        CHECK(raised.contrast_fitted[c]);
        CHECK(raised.s_photo[c] <= kHalfStep + 1e-9);
        CHECK(raised.s_photo[c] > kHalfStep - 1.0);
    }
    // Measured apart from the fit (256 samples per pixel, another seed, its
    // halves at the final size): the fitted material spreads as the photo
    // does, within the fit's tolerance and the measurement's own scatter.
    OpticalParams fitted = t.volume.optics;
    fitted.ks = raised.ks;
    fitted.contrast = raised.contrast;
    fitted.density_scale = raised.density_scale;
    OpticalParams mean_medium = fitted;
    mean_medium.contrast = {0.0, 0.0, 0.0};
    const MaterialVolumeMedium material(t.volume, t.volume.cube, fitted);
    const MaterialVolumeMedium shading(t.volume, t.volume.cube, mean_medium, material.majorant());
    RenderSettings measure;
    measure.spp = 256;
    measure.seed = 7;
    Scene scene = t.scene;
    scene.medium = &material;
    const SplitFilms r = render_halves(scene, PinholeCamera(t.camera), measure);
    scene.medium = &shading;
    const SplitFilms s = render_halves(scene, PinholeCamera(t.camera), measure);
    const MaterialSpread m = material_spread(r, s, raised.exposure, raised.material_block);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": S measured " << m.s[c] << " (noise " << m.noise[c] << ")");
        CHECK(std::abs(m.s[c] - raised.s_photo[c]) < options.s_tolerance + 1.0);
    }
}
