// Colour matching (paper §4.2): per-channel matching reproduces the photo's
// per-channel CDF in every slice; the background never matters; joint matching
// uses only real photo colours and keeps a minority colour's share.

#include "jade/volume/color_match.h"
#include "jade/volume/histogram.h"
#include "jade/volume/material_volume.h"
#include "jade/core/random.h"

#include <catch2/catch.hpp>

#include <set>

using namespace jade;

namespace {

// A photo whose channels have different, skewed distributions, with a
// transparent border that is bright green.
Photo synthetic_photo(int w, int h, std::uint64_t seed) {
    Photo p;
    p.width = w;
    p.height = h;
    p.levels.resize(std::size_t(w) * h);
    p.foreground.resize(p.levels.size());
    SplitMix64 rng(seed);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const double u = rng.uniform(), v = rng.uniform();
            p.levels[i] = {std::uint8_t(60 + 150 * u * u), std::uint8_t(30 + 200 * v),
                           std::uint8_t(90 + 40 * (u + v))};
            const bool border = x < w / 8 || y < h / 8 || x >= w - w / 8 || y >= h - h / 8;
            p.foreground[i] = !border;
            if (border) p.levels[i] = {0, 255, 0};
        }
    return p;
}

NoiseParams small_noise(int s) {
    NoiseParams n;
    n.resolution = s;
    n.seed = 3;
    return n;
}

}  // namespace

TEST_CASE("per-channel matching: every slice's CDF equals the photo's foreground CDF",
          "[color_match]") {
    const Photo photo = synthetic_photo(80, 60, 1);
    const RgbHistogram target = RgbHistogram::of(photo.foreground_levels());
    const int s = 32;
    const std::size_t m = std::size_t(s) * s;
    const MaterialVolume vol =
        build_material_volume(photo, small_noise(s), MatchMode::PerChannel, OpticalParams{});
    for (int z = 0; z < s; ++z) {
        const RgbHistogram got = RgbHistogram::of(&vol.levels[z * m], m);
        for (int c = 0; c < 3; ++c) {
            const auto fg = got.cdf(c), ft = target.cdf(c);
            for (int g = 0; g < 256; ++g) {
                // Vertically: the proportions agree to one voxel in M.
                REQUIRE(std::abs(fg[g] - ft[g]) <= 1.0 / double(m) + 1e-12);
                // Horizontally: each quantile lands within one gray level.
                const double u = (g + 0.5) / 256.0;
                REQUIRE(std::abs(got.quantile(c, u) - target.quantile(c, u)) <= 1);
            }
        }
    }
}

TEST_CASE("matching follows the noise: higher noise, higher rank, later table entry",
          "[color_match]") {
    std::vector<Rgb8> table(5);
    for (int r = 0; r < 5; ++r) table[r] = {std::uint8_t(r), 0, 0};
    const float noise[5] = {0.3f, -1.f, 2.f, 0.3f, 0.1f};
    Rgb8 out[5];
    match_slice(noise, 5, table, out);
    CHECK(out[1][0] == 0);  // lowest
    CHECK(out[4][0] == 1);
    CHECK(out[0][0] == 2);  // ties ranked by position
    CHECK(out[3][0] == 3);
    CHECK(out[2][0] == 4);  // highest
}

TEST_CASE("background pixels never influence the result", "[color_match]") {
    Photo a = synthetic_photo(64, 64, 7);
    Photo b = a;
    SplitMix64 rng(99);
    for (std::size_t i = 0; i < b.levels.size(); ++i)
        if (!b.foreground[i])
            b.levels[i] = {std::uint8_t(rng.below(256)), std::uint8_t(rng.below(256)),
                           std::uint8_t(rng.below(256))};
    for (MatchMode mode : {MatchMode::PerChannel, MatchMode::Joint}) {
        const auto va = build_material_volume(a, small_noise(24), mode, OpticalParams{});
        const auto vb = build_material_volume(b, small_noise(24), mode, OpticalParams{});
        CHECK(va.levels == vb.levels);
    }
}

TEST_CASE("joint matching uses only photo colours and keeps a 10% minority at 10%",
          "[color_match]") {
    // 90% grey stone with slight variation, 10% red veins, scattered.
    Photo p;
    p.width = 100;
    p.height = 100;
    SplitMix64 rng(5);
    std::set<std::uint32_t> present;
    for (int i = 0; i < 10000; ++i) {
        const bool red = rng.uniform() < 0.1;
        const int d = int(rng.below(21)) - 10;
        const Rgb8 c = red ? Rgb8{std::uint8_t(190 + d), 40, 45}
                           : Rgb8{std::uint8_t(120 + d), std::uint8_t(122 + d), std::uint8_t(125 + d)};
        p.levels.push_back(c);
        p.foreground.push_back(1);
        present.insert((c[0] << 16) | (c[1] << 8) | c[2]);
    }
    const double red_share_photo =
        double(std::count_if(p.levels.begin(), p.levels.end(), [](Rgb8 c) { return c[1] < 80; })) /
        p.levels.size();

    const int s = 40;
    const auto joint = build_material_volume(p, small_noise(s), MatchMode::Joint, OpticalParams{});
    std::size_t red = 0;
    for (const Rgb8& c : joint.levels) {
        REQUIRE(present.count((c[0] << 16) | (c[1] << 8) | c[2]) == 1);
        red += c[1] < 80;
    }
    // Quantile sampling keeps each colour's share to within one voxel per slice.
    CHECK(double(red) / joint.levels.size() == Approx(red_share_photo).margin(1.0 / (s * s)));

    // The paper's per-channel mode, on the same photo, invents colour triples.
    const auto per =
        build_material_volume(p, small_noise(s), MatchMode::PerChannel, OpticalParams{});
    std::size_t invented = 0;
    for (const Rgb8& c : per.levels) invented += present.count((c[0] << 16) | (c[1] << 8) | c[2]) == 0;
    CHECK(invented > per.levels.size() / 20);
}

TEST_CASE("match mode names parse and print", "[color_match]") {
    CHECK(parse_match_mode("joint") == MatchMode::Joint);
    CHECK(parse_match_mode("per-channel") == MatchMode::PerChannel);
    CHECK(std::string(to_string(MatchMode::PerChannel)) == "per-channel");
    CHECK_THROWS(parse_match_mode("both"));
}
