// The k_s drivers on known brightness functions (no rendering): the paper's
// stepping takes its number of steps, the bracketing search converges in a
// few renders (false position; halving from an end that clips), both stop when the target cannot be reached. And the display-space
// statistics of a film against hand-computed histograms.

#include "jade/fit/appearance.h"
#include "jade/fit/display.h"
#include "jade/fit/driver.h"
#include "jade/core/display.h"
#include "jade/core/random.h"
#include "jade/render/pixel_sampler.h"
#include "jade/render/renderer.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

using namespace jade;

namespace {

struct Run {
    int renders = 0;
    std::array<double, 3> k{};
    std::array<ChannelState, 3> state{};
};

// Drives `method` on A_c(k) = brightness[c](k) against targets, as the pipeline does.
Run drive(FitMethod method, const std::array<std::function<double(double)>, 3>& brightness,
          const std::array<double, 3>& target, const FitLimits& limits, int cap = 200) {
    FitDriver d(method, {0, 0, 0}, limits);
    Run r;
    while (!d.done() && r.renders < cap) {
        std::array<double, 3> delta;
        for (int c = 0; c < 3; ++c) delta[c] = brightness[c](d.k()[c]) - target[c];
        d.observe(delta);
        ++r.renders;
    }
    r.k = d.best_k();
    for (int c = 0; c < 3; ++c) r.state[c] = d.state(c);
    return r;
}

FitLimits limits() {
    FitLimits l;
    l.k_min = {-0.5, -0.5, -0.5};
    l.k_max = 20.0;
    return l;
}

}  // namespace

TEST_CASE("step driver: the paper's number of 0.01 steps", "[fitter]") {
    // A = 120 + 150 k: the target 140 is met (|dA| < 1) first at k = 0.13,
    // the 14th render (k = 0, 0.01, ..., 0.13). Channel 2 moves down.
    auto lin = [](double k) { return 120.0 + 150.0 * k; };
    const Run r = drive(FitMethod::Step, {lin, lin, lin}, {140.0, 120.5, 112.3}, limits());
    CHECK(r.state[0] == ChannelState::Converged);
    CHECK(r.k[0] == Approx(0.13));
    CHECK(r.k[1] == Approx(0.0));
    CHECK(r.k[2] == Approx(-0.05));  // 120 - 7.5 = 112.5, |dA| = 0.2
    CHECK(r.renders == 14);
}

TEST_CASE("bisect driver: O(log) renders on smooth and on saturating brightness", "[fitter]") {
    auto lin = [](double k) { return 120.0 + 150.0 * k; };
    auto sat = [](double k) { return 100.0 + 80.0 * (1.0 - std::exp(-k)); };  // flattens out
    auto steep = [](double k) { return 60.0 + 900.0 * k; };                   // one 0.01 step = 9 levels
    const Run r = drive(FitMethod::Bisect, {lin, sat, steep}, {170.0, 175.0, 73.0}, limits());
    for (int c = 0; c < 3; ++c) CHECK(r.state[c] == ChannelState::Converged);
    CHECK(std::abs(lin(r.k[0]) - 170.0) < 1.0);
    CHECK(std::abs(sat(r.k[1]) - 175.0) < 1.0);
    CHECK(std::abs(steep(r.k[2]) - 73.0) < 1.0);
    // A root 2.6 away needs 2.6 / 0.01 = 260 steps of the paper's driver.
    CHECK(r.renders <= 12);
}

TEST_CASE("the step driver reports a goal its steps jump over", "[fitter]") {
    auto steep = [](double k) { return 60.0 + 900.0 * k; };
    const Run r = drive(FitMethod::Step, {steep, steep, steep}, {73.0, 60.2, 73.0}, limits());
    CHECK(r.state[0] == ChannelState::Unreachable);
    CHECK(r.state[1] == ChannelState::Converged);
    CHECK(std::abs(steep(r.k[0]) - 73.0) <= 4.5);  // the best grid point is kept
    CHECK(r.renders < 10);
}

TEST_CASE("both drivers stop when no k_s reaches the target, in either direction", "[fitter]") {
    auto sat = [](double k) { return 100.0 + 80.0 * (1.0 - std::exp(-k)); };
    for (FitMethod m : {FitMethod::Step, FitMethod::Bisect}) {
        // Brighter than the material can be, and darker than at k_min = -0.5 (A = 48.1).
        const Run r = drive(m, {sat, sat, sat}, {200.0, 20.0, 150.0}, limits(), 100000);
        INFO(to_string(m));
        CHECK(r.state[0] == ChannelState::Unreachable);
        CHECK(r.state[1] == ChannelState::Unreachable);
        CHECK(r.state[2] == ChannelState::Converged);
        CHECK(r.k[0] == Approx(20.0));
        CHECK(r.k[1] == Approx(-0.5));
        if (m == FitMethod::Bisect) CHECK(r.renders <= 16);
        else CHECK(r.renders <= 2002);  // the paper's steps walk to k_max = 20
    }
    FitDriver none(FitMethod::None, {0.1, 0.2, 0.3}, limits());
    CHECK(none.done());
}

TEST_CASE("display statistics: exposure, sRGB, 8 bits, object pixels only", "[fitter]") {
    Film f(3, 1);
    // Pixels 0 and 1: linear 0.25 × exposure 2 = 0.5 (sRGB level 188),
    // covered; pixel 2 not covered, so it does not count.
    f.add_sample(0, 0, Spectrum(0.25f), true);
    f.add_sample(1, 0, Spectrum(0.25f), true);
    f.add_sample(2, 0, Spectrum(1.f), false);
    const DisplayStatistics s = display_statistics(f, 2.f);
    CHECK(s.pixels == 2);
    const int level = int(std::lround(255.0 * srgb_encode(0.5)));
    CHECK(s.a[0] == Approx(level));
    CHECK(s.histogram.proportion(1, level) == Approx(1.0));
}

TEST_CASE("bisect from renders at both bounds: bracketed channels narrow, the others stop", "[fitter]") {
    auto sat = [](double k) { return 100.0 + 80.0 * (1.0 - std::exp(-k)); };  // 48.1 at -0.5, 178.5 at 4
    FitLimits l = limits();
    l.k_max = 4.0;
    FitDriver d(FitMethod::Bisect, {0, 0, 0}, l);
    const std::array<double, 3> target{150.0, 190.0, 30.0};
    std::array<double, 3> lo, hi;
    for (int c = 0; c < 3; ++c) {
        lo[c] = sat(-0.5) - target[c];
        hi[c] = sat(4.0) - target[c];
    }
    d.observe_bounds(lo, hi);
    CHECK(d.state(1) == ChannelState::Unreachable);  // darker than the photo at k_max
    CHECK(d.state(2) == ChannelState::Unreachable);  // brighter at k_min
    // The chord's root: -0.5 + 4.5 · 101.898 / (101.898 + 28.535).
    CHECK(d.k()[0] == Approx(-0.5 + 4.5 * (150.0 - sat(-0.5)) / (sat(4.0) - sat(-0.5))));
    CHECK(d.k()[0] == Approx(3.0155).margin(1e-4));
    int renders = 2;
    while (!d.done() && renders < 50) {
        d.observe({sat(d.k()[0]) - target[0], 0.0, 0.0});
        ++renders;
    }
    CHECK(d.state(0) == ChannelState::Converged);
    CHECK(std::abs(sat(d.best_k()[0]) - 150.0) < 1.0);
    // Where A saturates the chord lands on the bright side again and again;
    // Illinois' halving of the dark end takes it across in 5 renders. Plain
    // false position takes 9 here, halving the bracket 6.
    CHECK(renders <= 2 + 5);
}

TEST_CASE("bisect: on a straight A the chord from the bounds lands on the root", "[fitter]") {
    // A = 120 + 20 k over [-0.5, 4]: the photo's 150 at k = 1.5, one render
    // after the bounds (halving the bracket would take 4).
    auto lin = [](double k) { return 120.0 + 20.0 * k; };
    FitLimits l = limits();
    l.k_max = 4.0;
    FitDriver d(FitMethod::Bisect, {0, 0, 0}, l);
    d.observe_bounds({lin(-0.5) - 150.0, lin(-0.5) - 150.0, lin(-0.5) - 150.0},
                     {lin(4.0) - 150.0, lin(4.0) - 150.0, lin(4.0) - 150.0});
    for (int c = 0; c < 3; ++c) CHECK(d.k()[c] == Approx(1.5));
    const double delta = lin(d.k()[0]) - 150.0;
    d.observe({delta, delta, delta});
    CHECK(d.done());
    for (int c = 0; c < 3; ++c) CHECK(d.state(c) == ChannelState::Converged);
}

TEST_CASE("bisect: a bracket's end whose render clips is halved from, not drawn through", "[fitter]") {
    // A near-white photo (A 248): A rises steeply from k_min and is flat at
    // 255 above (most pixels clipped, so a render's A there is only a bound).
    // The chord through (4, +7) lands near k = 4 render after render.
    auto clip = [](double k) { return 255.0 - 100.0 * std::exp(-25.0 * (k + 0.96)); };
    auto renders_to_converge = [&](bool tell_clipped) {
        FitLimits l;
        l.k_min = {-0.96, -0.96, -0.96};
        l.k_max = 4.0;
        FitDriver d(FitMethod::Bisect, {0, 0, 0}, l);
        auto delta = [&](double k) { return std::array<double, 3>{clip(k) - 248.0, 0.0, 0.0}; };
        auto clipped = [&](double k) { return std::array<bool, 3>{tell_clipped && clip(k) > 254.0, false, false}; };
        d.observe_bounds(delta(-0.96), delta(4.0), clipped(-0.96), clipped(4.0));
        int renders = 2;
        while (!d.done() && renders < 50) {
            const double k = d.k()[0];
            d.observe(delta(k), clipped(k));
            ++renders;
        }
        CHECK(d.state(0) == ChannelState::Converged);
        CHECK(std::abs(clip(d.best_k()[0]) - 248.0) < 1.0);
        return renders;
    };
    const int halved = renders_to_converge(true);
    const int chord = renders_to_converge(false);
    INFO("halved from the clipped end: " << halved << " renders, drawn through it: " << chord);
    // Halving reaches A's rise (0.16 wide) in log2(4.96 / 0.16) = 5 renders,
    // and the chord takes it from there: 10 in all. The chord alone moves
    // 7 / (7 + 93) of the bracket at first, and Illinois' halvings of the
    // dark end's ΔA take 14.
    CHECK(halved <= 10);
    CHECK(halved < chord);
}

TEST_CASE("A is corrected for the bias noise puts into a concave display curve", "[fitter]") {
    // Pixels of true linear value 0.3, each the mean of 4 samples uniform on
    // [0, 0.6]: the mean of their sRGB levels lies ~1.7 levels below
    // 255·srgb(0.3); the corrected A must not.
    const int n = 128, spp = 4;
    Film f(n, n);
    SplitMix64 rng(11);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int s = 0; s < spp; ++s) f.add_sample(x, y, Spectrum(float(0.6 * rng.uniform())), true);
    const DisplayStatistics st = display_statistics(f, 1.f);
    const double truth = 255.0 * srgb_encode(0.3);
    INFO("A " << st.a[0] << " (histogram " << st.histogram.mean(0) << ") vs " << truth << " +- " << st.a_sigma[0]);
    CHECK(st.histogram.mean(0) < truth - 1.0);                     // the raw mean is biased low
    CHECK(std::abs(st.a[0] - truth) < 4 * st.a_sigma[0] + 0.05);  // the corrected one is not
}

namespace {

// A 96² render in two halves whose pixels lie on a ramp of linear values
// from `low` to `high`, 16 samples a pixel laid out as the renderer lays
// them (heroes in turns, turns in four replicates, the halves replicates 0–1
// and 2–3), each sample the pixel's value times draw(rng), a draw of mean 1;
// and the converged render's mean level.
struct RampRender {
    SplitFilms render{Film(96, 96), Film(96, 96)};
    double truth = 0.0;
    RampRender(double low, double high, std::uint64_t seed, const std::function<double(SplitMix64&)>& draw) {
        const int n = 96, spp = 16;
        SplitMix64 rng(seed);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double mu = low + (high - low) * (y * n + x) / double(n * n - 1);
                truth += std::floor(255.0 * srgb_encode(std::min(mu, 1.0)) + 0.5) / double(n * n);
                for (int i = 0; i < spp; ++i) {
                    const int replicate = sample_replicate(std::uint64_t(i));
                    (replicate < 2 ? render.first : render.second)
                        .add_sample(x, y, Spectrum(float(mu * draw(rng))), true, i % Film::kStrata, replicate);
                }
            }
    }
};

// 0.4 with probability 0.9, 6.4 with 0.1: as the light's rare bright paths make them.
double heavy_tailed(SplitMix64& rng) { return rng.uniform() < 0.1 ? 6.4 : 0.4; }

}  // namespace

TEST_CASE("A at the final size: Richardson's extrapolation from the halves removes the noise's bias",
          "[fitter]") {
    // Pixels from 0.05 to 0.8, heavy-tailed draws. The raw levels read low
    // (the concave curve); the extrapolated A must be the converged render's
    // within its own noise. (Measured: the whole's raw mean 6.2 levels low,
    // the extrapolation 0.1 off; extrapolated from the means the delta
    // method corrected, whose variances the halves and the whole estimate
    // differently, 2.1 levels high.) Near white: the next test.
    const RampRender r(0.05, 0.8, 23, heavy_tailed);
    const DisplayStatistics whole = display_statistics(r.render.merged(), 1.f);
    const std::array<double, 3> a = extrapolated_brightness(r.render, 1.f);
    INFO("A extrapolated " << a[0] << ", converged " << r.truth << "; the whole's raw mean "
                           << whole.histogram.mean(0) << ", corrected " << whole.a[0] << "; standard error "
                           << whole.a_sigma[0]);
    CHECK(whole.histogram.mean(0) < r.truth - 1.0);  // the noise's bias is there to take out
    CHECK(std::abs(a[0] - r.truth) < 4.0 * whole.a_sigma[0]);
}

TEST_CASE("A at the final size: near white, the clip's bias falls as 1/spp, the rare bright samples' does not",
          "[fitter]") {
    // Pixels from 0.5 to 1.5 (half of them at level 255 when converged). A
    // pixel within its noise of the clip is biased as 1/√spp, but over a
    // spread of pixel values only those within the noise of the clip are,
    // so with exponential draws the mean level's bias still falls as 1/spp
    // and the halves' extrapolation takes it out. With heavy-tailed draws
    // the energy of a bright sample in a pixel near white is lost at the
    // clip, at 16 samples as at 8, and the extrapolation reads more than a
    // level low: why the fit's brightness check renders both sizes at equal
    // samples per pixel where many pixels are white
    // (FitSession::final_brightness; docs/design.md, "The fit").
    const auto extrapolation_error = [](const std::function<double(SplitMix64&)>& draw) {
        const RampRender r(0.5, 1.5, 29, draw);
        const DisplayStatistics whole = display_statistics(r.render.merged(), 1.f);
        INFO("the whole's raw mean " << whole.histogram.mean(0) << " against " << r.truth);
        CHECK(whole.histogram.mean(0) < r.truth - 2.0);  // a bias to take out
        return std::array<double, 2>{extrapolated_brightness(r.render, 1.f)[0] - r.truth, whole.a_sigma[0]};
    };
    const auto exponential = extrapolation_error([](SplitMix64& rng) { return -std::log(1.0 - rng.uniform()); });
    INFO("exponential draws: extrapolated A less the converged " << exponential[0] << " +- " << exponential[1]);
    CHECK(std::abs(exponential[0]) < 4.0 * exponential[1]);
    const auto heavy = extrapolation_error(heavy_tailed);
    INFO("heavy-tailed draws: " << heavy[0] << " +- " << heavy[1]);
    CHECK(heavy[0] < -1.0);
    CHECK(heavy[0] < -4.0 * heavy[1]);
}

TEST_CASE("noise-clipped share: the pixels whose clip at white one half of the samples decides", "[fitter]") {
    // Pixels on a ramp of linear values from 0.3 to 3 (below, near and far
    // above white), 8 samples in each half, each the pixel's value times an
    // exponential draw of mean 1. All in one stratum, so that a half's mean
    // is the plain mean: value × Gamma(8, 1/8). A half shows the pixel at 255
    // where that mean reaches the level's edge w, with probability p =
    // P(Gamma(8, 1) ≥ 8w/value) = Σ_{k<8} e^(−x) x^k / k!, x = 8w/value;
    // the halves disagree with probability 2p(1 − p). The share must be that
    // over the ramp, within four standard deviations of the pixels' count.
    const int n = 96, per_half = 8;
    const double low = 0.3, high = 3.0;
    const double w = srgb_decode(254.5 / 255.0);
    SplitFilms render{Film(n, n), Film(n, n)};
    SplitMix64 rng(31);
    double expected = 0.0, variance = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double value = low + (high - low) * (y * n + x) / double(n * n - 1);
            for (int h = 0; h < 2; ++h)
                for (int i = 0; i < per_half; ++i)
                    (h == 0 ? render.first : render.second)
                        .add_sample(x, y, Spectrum(float(value * -std::log(1.0 - rng.uniform()))), true, 0, 2 * h);
            const double t = per_half * w / value;
            // P(Gamma(8, 1) ≥ t): fewer than 8 events of a Poisson process of mean t.
            double p = 0.0, term = std::exp(-t);
            for (int k = 0; k < per_half; ++k) {
                p += term;
                term *= t / (k + 1);
            }
            const double q = 2.0 * p * (1.0 - p);
            expected += q;
            variance += q * (1.0 - q);
        }
    const double pixels = double(n) * n;
    expected /= pixels;
    const double sigma = std::sqrt(variance) / pixels;
    const std::array<double, 3> share = noise_clipped_share(render, 1.f);
    INFO("share " << share[0] << ", expected " << expected << " +- " << sigma);
    CHECK(expected > 0.05);  // the ramp's pixels near white make a share to measure
    for (int c = 0; c < 3; ++c) CHECK(std::abs(share[c] - expected) < 4.0 * sigma);
    // Far from white on either side no half disagrees: a film of 0.1 and one of 30.
    for (const double value : {0.1, 30.0}) {
        SplitFilms flat{Film(8, 8), Film(8, 8)};
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                for (int h = 0; h < 2; ++h)
                    for (int i = 0; i < per_half; ++i)
                        (h == 0 ? flat.first : flat.second)
                            .add_sample(x, y, Spectrum(float(value * (0.75 + 0.5 * rng.uniform()))), true, 0, 2 * h);
        CHECK(noise_clipped_share(flat, 1.f)[0] == 0.0);
    }
}

TEST_CASE("the fitting exposure lies where every channel can reach the photo, and is always finite",
          "[fitter]") {
    // One-pixel films: linear value v shows as level round(255 srgb(e v)).
    auto film = [](Spectrum v) {
        Film f(1, 1);
        f.add_sample(0, 0, v, true);
        return f;
    };
    auto exposure_for = [](double linear, double level) {  // e with 255 srgb(e v) = level
        return srgb_decode(level / 255.0) / linear;
    };
    const Film lo = film(Spectrum(0.02f, 0.04f, 0.05f));
    const Film hi = film(Spectrum(0.2f, 0.3f, 0.4f));
    const std::array<double, 3> photo{150, 120, 100};
    // Channel c reaches the photo for e in [photo at hi, photo at lo]; the
    // shared range is [max over c of the first, min over c of the second].
    double lower = 0, upper = 1e9;
    for (int c = 0; c < 3; ++c) {
        lower = std::max(lower, exposure_for(hi.mean(0, 0)[c], photo[c]));
        upper = std::min(upper, exposure_for(lo.mean(0, 0)[c], photo[c]));
    }
    REQUIRE(lower < upper);
    const double e = exposure_in_reach(lo, hi, photo);
    // Levels are integers, so the bounds found on them are within a level's width.
    CHECK(e == Approx(std::sqrt(lower * upper)).epsilon(0.02));
    CHECK(e > lower);
    CHECK(e < upper);

    // A black render at k_max (no exposure can brighten it) and an empty one:
    // finite, positive, inside [1e-4, 1e4].
    const Film black = film(Spectrum(0.f));
    const double x = exposure_in_reach(black, black, photo);
    CHECK(std::isfinite(x));
    CHECK(x >= 1e-4);
    CHECK(x <= 1e4);
    const double empty = exposure_in_reach(Film(2, 2), Film(2, 2), photo);
    CHECK(std::isfinite(empty));
    CHECK(empty > 0);
}

TEST_CASE("S: the spread of the levels less what the pixels' noise adds", "[fitter][appearance]") {
    // Left half of linear value 0.1, right half 0.4; each pixel the mean of
    // 4 samples uniform on [0, 2·value]. The converged render's S is half the
    // distance between the two levels.
    const int n = 128, spp = 4;
    Film f(n, n);
    SplitMix64 rng(5);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double value = x < n / 2 ? 0.1 : 0.4;
            for (int s = 0; s < spp; ++s) f.add_sample(x, y, Spectrum(float(2.0 * value * rng.uniform())), true);
        }
    const DisplayStatistics st = display_statistics(f, 1.f);
    const double truth = 0.5 * 255.0 * (srgb_encode(0.4) - srgb_encode(0.1));
    INFO("S " << st.s[0] << " (histogram " << st.histogram.spread(0) << ") vs " << truth);
    CHECK(st.histogram.spread(0) > truth + 1.0);               // the raw spread holds the noise
    CHECK(std::abs(st.s[0] - truth) < 0.02 * truth + 0.3);     // the corrected one does not
    RgbHistogram two;
    two.counts[1][10] = two.counts[1][30] = 5;
    two.total = 10;
    CHECK(two.spread(1) == Approx(10.0));
}

TEST_CASE("render pixels per cube side follow the camera's footprint", "[fitter][appearance]") {
    CameraParams cam;
    cam.origin = {0.f, 0.f, 2.f};
    cam.target = {0.f, 0.f, 0.f};
    cam.fov_degrees = 90.f;
    cam.width = 100;
    Cube cube;  // [-0.5, 0.5]^3, centre at the origin: 2 units away
    // One pixel covers 2·2·tan(45°)/100 = 0.04 units: 25 pixels per side.
    CHECK(render_pixels_per_side(cam, cube) == Approx(25.0).epsilon(1e-6));
}
