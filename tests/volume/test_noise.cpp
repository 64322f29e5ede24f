// Noise (paper §4.1, Table 1): determinism, bounds, thread independence, and
// the octave schedule checked through its spectrum and variance.

#include "jade/volume/noise.h"
#include "jade/core/math.h"
#include "jade/core/random.h"

#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstring>
#include <vector>

using namespace jade;

namespace {

NoiseParams params(int s, int octaves, double k, std::uint32_t seed) {
    NoiseParams p;
    p.resolution = s;
    p.octaves = octaves;
    p.k = k;
    p.seed = seed;
    return p;
}

// Fraction of the (Hann-windowed, mean-removed) power of lines along x at
// DFT bins >= min_bin, averaged over a grid of lines through the volume.
double power_fraction_above(const std::vector<float>& vol, int s, int min_bin) {
    const double pi = std::acos(-1.0);
    double above = 0.0, total = 0.0;
    std::vector<double> line(s);
    for (int z = 1; z < s; z += s / 8)
        for (int y = 1; y < s; y += s / 8) {
            double mean = 0.0;
            for (int x = 0; x < s; ++x) mean += vol[(std::size_t(z) * s + y) * s + x];
            mean /= s;
            for (int x = 0; x < s; ++x) {
                const double w = 0.5 - 0.5 * std::cos(2 * pi * (x + 0.5) / s);
                line[x] = (vol[(std::size_t(z) * s + y) * s + x] - mean) * w;
            }
            for (int b = 1; b <= s / 2; ++b) {
                std::complex<double> acc = 0.0;
                for (int x = 0; x < s; ++x) acc += line[x] * std::polar(1.0, -2 * pi * b * x / s);
                const double p = std::norm(acc);
                total += p;
                if (b >= min_bin) above += p;
            }
        }
    return above / total;
}

}  // namespace

TEST_CASE("octave count follows Table 1: n = log2(s)", "[noise]") {
    CHECK(params(256, 0, 0.5, 1).octave_count() == 8);
    CHECK(params(128, 0, 0.5, 1).octave_count() == 7);
    CHECK(params(100, 0, 0.5, 1).octave_count() == 6);  // floor(log2(100))
    CHECK(params(256, 3, 0.5, 1).octave_count() == 3);
}

TEST_CASE("frequency and amplitude schedule follow Table 1", "[noise]") {
    const Fbm fbm(params(256, 0, 0.4, 7));
    REQUIRE(fbm.octaves() == 8);
    for (int i = 0; i < 8; ++i) {
        CHECK(fbm.frequency(i) == Approx(std::pow(2.0, i) / 256.0).epsilon(1e-15));
        CHECK(fbm.amplitude(i) == Approx(std::pow(0.4, i + 1)).epsilon(1e-12));
    }
}

TEST_CASE("noise is deterministic for a seed and differs between seeds", "[noise]") {
    const auto a = fbm_volume(params(32, 0, 0.5, 42));
    const auto b = fbm_volume(params(32, 0, 0.5, 42));
    const auto c = fbm_volume(params(32, 0, 0.5, 43));
    CHECK(a == b);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != c[i];
    CHECK(differ > a.size() * 99 / 100);
}

TEST_CASE("noise is identical with one and with two threads", "[noise]") {
    std::vector<float> one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = fbm_volume(params(48, 0, 0.6, 5));
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = fbm_volume(params(48, 0, 0.6, 5));
    }
    CHECK(one == two);
}

TEST_CASE("simplex noise stays within its analytic bound of 1, fBm within sum of amplitudes",
          "[noise]") {
    const SimplexNoise noise(3);
    SplitMix64 rng(11);
    double max_abs = 0.0;
    for (int i = 0; i < 1000000; ++i) {
        const double v = noise(rng.uniform() * 300, rng.uniform() * 300, rng.uniform() * 300);
        max_abs = std::max(max_abs, std::abs(v));
    }
    CHECK(max_abs <= 1.0);
    CHECK(max_abs > 0.2);  // and it is not degenerate

    const NoiseParams p = params(64, 0, 0.7, 9);
    const Fbm fbm(p);
    for (float v : fbm_volume(p)) REQUIRE(std::abs(v) <= fbm.bound());
}

TEST_CASE("simplex noise four points at a time gives each point's value bit for bit", "[noise]") {
    // Random points over a wide range, their negatives (the floor below 0),
    // points on the lattice and on the skewed cube's diagonals (the
    // corner choice's ties), each lane's point different.
    const SimplexNoise noise(23);
    SplitMix64 rng(31);
    std::vector<std::array<double, 3>> points;
    for (int i = 0; i < 40000; ++i) {
        const double scale = i % 3 == 0 ? 3.0 : i % 3 == 1 ? 300.0 : 3e5;
        std::array<double, 3> p{(rng.uniform() - 0.5) * scale, (rng.uniform() - 0.5) * scale,
                                (rng.uniform() - 0.5) * scale};
        points.push_back(p);
    }
    for (int i = -8; i <= 8; ++i)
        for (double f : {0.0, 0.5, 1.0 / 3.0, 2.0 / 3.0}) {
            points.push_back({i + f, i + f, i + f});
            points.push_back({i + f, double(i), -i - f});
        }
    while (points.size() % 4) points.push_back({0.0, 0.0, 0.0});
    std::size_t differ = 0;
    for (std::size_t i = 0; i < points.size(); i += 4) {
        SimplexNoise::Lanes x, y, z;
        for (int l = 0; l < 4; ++l) x[l] = points[i + l][0], y[l] = points[i + l][1], z[l] = points[i + l][2];
        const SimplexNoise::Lanes v = noise(x, y, z);
        for (int l = 0; l < 4; ++l) {
            const double one = noise(x[l], y[l], z[l]);
            if (std::memcmp(&one, &v[l], sizeof one) != 0) ++differ;
        }
    }
    CHECK(differ == 0);
}

TEST_CASE("an fBm slice, made four voxels at a time, holds each voxel's value", "[noise]") {
    // Every kind of structure, on a row length that is not a multiple of
    // four; each voxel against the fBm at that one position.
    NoiseParams plain = params(37, 0, 0.5, 4);
    NoiseParams oriented = plain;
    oriented.frequency = 3.0, oriented.stretch = 2.5, oriented.angle = 33.0;
    NoiseParams bands = plain;
    bands.bands = 6, bands.warp = 0.3, bands.fold = 0.4;
    NoiseParams layers = bands;
    layers.layers = true, layers.k = 0.85, layers.fold = 0.05;
    NoiseParams veins = layers;
    veins.veins = true, veins.vein_width = 0.05;
    for (const NoiseParams& p : {plain, oriented, bands, layers, veins}) {
        const Fbm fbm(p);
        std::vector<float> slice(std::size_t(p.resolution) * p.resolution);
        fbm_slice(fbm, p.resolution, 11, slice.data());
        std::size_t differ = 0;
        for (int j = 0; j < p.resolution; ++j)
            for (int i = 0; i < p.resolution; ++i)
                differ += slice[std::size_t(j) * p.resolution + i] != float(fbm(i + 0.5, j + 0.5, 11.5));
        INFO("bands " << p.bands << ", layers " << p.layers << ", veins " << p.veins);
        CHECK(differ == 0);
    }
}

TEST_CASE("noise is continuous: neighbouring samples differ by at most the gradient bound",
          "[noise]") {
    // Kernel radius^2 = 1/2 keeps each corner's support inside its simplices;
    // a seam would show as a jump far above the Lipschitz bound.
    const SimplexNoise noise(17);
    SplitMix64 rng(5);
    const double h = 1e-6;
    double worst = 0.0;
    for (int i = 0; i < 200000; ++i) {
        const double x = rng.uniform() * 50, y = rng.uniform() * 50, z = rng.uniform() * 50;
        worst = std::max(worst, std::abs(noise(x + h, y, z) - noise(x, y, z)) / h);
    }
    CHECK(worst < 50.0);  // |grad| <= 4 corners * scale * max|d/dr (R^2-r^2)^4 g.d| ~ 26
}

TEST_CASE("a single-octave volume has no energy above its frequency band", "[noise]") {
    // Octave i alone is fbm(i + 1 octaves) - fbm(i octaves). Its frequency is
    // Fr_i = 2^i / s, i.e. DFT bin 2^i along a line of s voxels. Its power must
    // lie in its band: under 0.2% from bin 4 * 2^i up (the kernel's smooth
    // tail; measured <= 3e-4), and over 10% from bin 2^i up (measured 15-52%).
    // An octave at twice its frequency breaks the first bound (~20% there), one
    // at half its frequency the second (~0.2% there).
    const int s = 128;
    std::vector<float> previous(std::size_t(s) * s * s, 0.f);
    for (int i = 0; i < 4; ++i) {
        std::vector<float> octave = fbm_volume(params(s, i + 1, 0.5, 21));
        std::vector<float> next = octave;
        for (std::size_t v = 0; v < octave.size(); ++v) octave[v] -= previous[v];
        INFO("octave " << i);
        CHECK(power_fraction_above(octave, s, 4 << i) < 2e-3);
        CHECK(power_fraction_above(octave, s, 1 << i) > 0.1);
        previous = std::move(next);
    }
    // The whole schedule reaches the high bins that a single low octave leaves empty.
    CHECK(power_fraction_above(fbm_volume(params(s, 7, 0.8, 21)), s, 16) > 2e-2);
}

TEST_CASE("each octave adds k times the previous amplitude: variance ratio k^2", "[noise]") {
    // Over a domain of many lattice cells every octave has the same variance
    // (the noise is stationary), so Var(fbm_2 - fbm_1) / Var(fbm_1) = (k^2/k)^2.
    for (double k : {0.3, 0.5, 0.8}) {
        const Fbm f1(params(64, 1, k, 13)), f2(params(64, 2, k, 13));
        SplitMix64 rng(77);
        double s1 = 0, s11 = 0, sd = 0, sdd = 0;
        const int n = 400000;
        for (int i = 0; i < n; ++i) {
            const double x = rng.uniform() * 64 * 40, y = rng.uniform() * 64 * 40,
                         z = rng.uniform() * 64 * 40;
            const double a = f1(x, y, z), b = f2(x, y, z) - a;
            s1 += a;
            s11 += a * a;
            sd += b;
            sdd += b * b;
        }
        const double var1 = s11 / n - (s1 / n) * (s1 / n);
        const double vard = sdd / n - (sd / n) * (sd / n);
        CHECK(vard / var1 == Approx(k * k).epsilon(0.05));
    }
}

TEST_CASE("noise parameters out of range are rejected", "[noise]") {
    CHECK_THROWS(params(1, 0, 0.5, 1).validate());
    CHECK_THROWS(params(64, 0, 1.0, 1).validate());
    CHECK_THROWS(params(64, 0, 0.0, 1).validate());
    CHECK_THROWS(params(64, -1, 0.5, 1).validate());
    CHECK_NOTHROW(params(64, 0, 0.5, 1).validate());
}

namespace {

// The share of the slice's darkest 5 % of pixels (its lowest values) that
// touch a pixel outside them (4-neighbours): near 1 for thin lines, lower for
// blobs, whose inside pixels touch only their own.
double darkest_edge_share(const std::vector<float>& slice, int s) {
    std::vector<float> sorted = slice;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 20, sorted.end());
    const float threshold = sorted[sorted.size() / 20];
    auto dark = [&](int x, int y) { return slice[std::size_t(y) * s + x] < threshold; };
    int n = 0, edge = 0;
    for (int y = 1; y + 1 < s; ++y)
        for (int x = 1; x + 1 < s; ++x)
            if (dark(x, y)) {
                ++n;
                edge += !dark(x - 1, y) || !dark(x + 1, y) || !dark(x, y - 1) || !dark(x, y + 1);
            }
    return double(edge) / n;
}

}  // namespace

TEST_CASE("veins: thin curves along a second fBm's zero set, below the structure, which keeps its values "
          "elsewhere", "[noise]") {
    NoiseParams plain = params(256, 0, 0.5, 5);
    plain.frequency = 2.0;
    NoiseParams veins = plain;
    veins.veins = true;
    const Fbm f(plain), v(veins);
    // Every point is either the structure's own value or a vein's, and a
    // vein's lies below every value the structure can take.
    SplitMix64 rng(11);
    int inside = 0;
    for (int i = 0; i < 20000; ++i) {
        const double x = 256 * rng.uniform(), y = 256 * rng.uniform(), z = 256 * rng.uniform();
        const double a = f(x, y, z), b = v(x, y, z);
        REQUIRE((b == a || b < -f.bound()));
        REQUIRE(std::abs(b) <= v.bound());
        inside += b < -f.bound();
    }
    // The veins are sheets of half-width w about a surface: for small w
    // their share of the volume grows as w does.
    NoiseParams wider = veins;
    wider.vein_width = 2.0 * veins.vein_width;
    const Fbm w(wider);
    int inside_wider = 0;
    SplitMix64 again(11);
    for (int i = 0; i < 20000; ++i) {
        const double x = 256 * again.uniform(), y = 256 * again.uniform(), z = 256 * again.uniform();
        inside_wider += w(x, y, z) < -f.bound();
    }
    CAPTURE(inside, inside_wider);
    // The default width gives them 7.5 % of the volume (measured): thin,
    // and enough of it for the photo's darkest colours.
    CHECK(inside > 200);
    CHECK(inside < 3000);
    CHECK(double(inside_wider) / inside == Approx(2.0).epsilon(0.2));
    // The darkest values lie along curves in a slice (the 3D zero set is a
    // surface); the darkest of the structure alone are the bottoms of its
    // basins, blobs.
    std::vector<float> a(256 * 256), b(256 * 256);
    fbm_slice(f, 256, 100, a.data());
    fbm_slice(v, 256, 100, b.data());
    const double blobs = darkest_edge_share(a, 256), lines = darkest_edge_share(b, 256);
    CAPTURE(blobs, lines);
    CHECK(lines > 0.75);  // 0.91 measured
    CHECK(blobs < 0.4);   // 0.26 measured
}

namespace {

// The lengths between successive crossings of the median along a line of n
// values: how thick the layers it crosses are.
std::vector<double> crossing_gaps(const std::vector<double>& line) {
    std::vector<double> sorted = line;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    std::vector<double> gaps;
    int last = -1;
    for (std::size_t i = 1; i < line.size(); ++i)
        if ((line[i - 1] < median) != (line[i] < median)) {
            if (last >= 0) gaps.push_back(double(int(i) - last));
            last = int(i);
        }
    return gaps;
}

double coefficient_of_variation(const std::vector<double>& v) {
    double mean = 0.0, sq = 0.0;
    for (double x : v) mean += x;
    mean /= double(v.size());
    for (double x : v) sq += (x - mean) * (x - mean);
    return std::sqrt(sq / double(v.size())) / mean;
}

}  // namespace

TEST_CASE("layers: a profile across the layers, constant along them, of many thicknesses where the sine's are "
          "alike", "[noise]") {
    NoiseParams sine = params(256, 0, 0.85, 3);
    sine.bands = 8.0, sine.warp = 0.0, sine.angle = 30.0;
    NoiseParams layered = sine;
    layered.layers = true;
    const Fbm s(sine), l(layered);
    const double c = std::cos(30.0 * kPiD / 180.0), d = std::sin(30.0 * kPiD / 180.0);
    // Unwarped, the value depends only on the position across the layers:
    // the same at every point of a line along them, in any slice.
    SplitMix64 rng(5);
    for (int i = 0; i < 200; ++i) {
        const double x = 256 * rng.uniform(), y = 256 * rng.uniform(), z = 256 * rng.uniform();
        const double t = 300.0 * (rng.uniform() - 0.5);
        REQUIRE(l(x + t * c, y + t * d, z) == Approx(l(x, y, 0.0)).margin(1e-9));
    }
    // Across them: the sine's layers are all as thick (8 per side, its
    // crossings 16 voxels apart); the profile's octaves, from 8 layers per
    // side to the grid's Nyquist frequency at amplitude ratio 0.85, make thin
    // and thick ones (the thicknesses' spread 1.38 times their mean measured).
    std::vector<double> across_sine, across_layers;
    for (int i = 0; i < 4096; ++i) {
        const double t = i / 16.0;  // 256 voxels, 16 points a voxel
        across_sine.push_back(s(128.0 - t * d, t * c, 50.0));
        across_layers.push_back(l(128.0 - t * d, t * c, 50.0));
    }
    const std::vector<double> gs = crossing_gaps(across_sine), gl = crossing_gaps(across_layers);
    CAPTURE(gs.size(), gl.size(), coefficient_of_variation(gs), coefficient_of_variation(gl));
    CHECK(coefficient_of_variation(gs) < 0.02);
    CHECK(coefficient_of_variation(gl) > 0.5);
    CHECK(gl.size() > 2 * gs.size());
    // The bound holds: the profile's amplitudes sum to it.
    layered.warp = 1.4;
    const Fbm warped(layered);
    for (int i = 0; i < 20000; ++i)
        REQUIRE(std::abs(warped(256 * rng.uniform(), 256 * rng.uniform(), 256 * rng.uniform())) <= warped.bound());
}

TEST_CASE("layers need bands", "[noise]") {
    NoiseParams p = params(64, 0, 0.5, 1);
    p.layers = true;
    REQUIRE_THROWS_WITH(p.validate(), Catch::Contains("--layers needs --bands"));
    p.bands = 4.0;
    REQUIRE_NOTHROW(p.validate());
}

TEST_CASE("fold: at 0 every layer folds alike and none turns back, at 1 the warp overturns them", "[noise]") {
    // The sine's layers under a strong warp (a·f_0 = 2.8, ten times what
    // overturns a fold, docs/design.md "Structure"), at angle 0: across the
    // layers is +y. At fold 0 the warp is read at the same point for every
    // layer of a line across them, so along such a line the value is the
    // sine itself shifted, its crossings of the median exactly half a layer
    // apart (256 / 8 / 2 = 16 voxels). At fold 1 the warp changes along the line
    // and the crossings bunch, spread, and come back where a fold overturns.
    NoiseParams folded = params(256, 0, 0.5, 11);
    folded.bands = 8.0, folded.warp = 1.4, folded.frequency = 2.0, folded.fold = 0.0;
    NoiseParams overturned = folded;
    overturned.fold = 1.0;
    const Fbm f(folded), o(overturned);
    SplitMix64 rng(8);
    for (int line = 0; line < 8; ++line) {
        const double x = 256 * rng.uniform(), z = 256 * rng.uniform();
        std::vector<double> across_f, across_o;
        for (int i = 0; i < 4096; ++i) {
            across_f.push_back(f(x, i / 16.0, z));
            across_o.push_back(o(x, i / 16.0, z));
        }
        const std::vector<double> gf = crossing_gaps(across_f), go = crossing_gaps(across_o);
        CAPTURE(line, gf.size(), go.size(), coefficient_of_variation(gf), coefficient_of_variation(go));
        REQUIRE(gf.size() >= 14);
        // 16 voxels of 16 samples each, to a sample.
        for (double gap : gf) REQUIRE(gap == Approx(256.0).margin(1.0));
        CHECK(coefficient_of_variation(go) > 0.2);
    }
    // Fold is a share between 0 and 1.
    folded.fold = 1.5;
    REQUIRE_THROWS_WITH(folded.validate(), Catch::Contains("--fold must be between 0"));
    folded.fold = -0.1;
    REQUIRE_THROWS_WITH(folded.validate(), Catch::Contains("--fold must be between 0"));
}
