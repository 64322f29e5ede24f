// Coefficients (paper §5.1) and the volume build.

#include "jade/volume/material_volume.h"

#include <catch2/catch.hpp>
#include <tbb/global_control.h>

using namespace jade;

TEST_CASE("coefficients follow §5.1 exactly for known v_c", "[material_volume]") {
    OpticalParams p;  // the paper's values: d_s = 1, d_a = 0.1, k_s = 0
    p.extinction = Extinction::Paper;
    p.da = 0.1;
    // level 128 -> v_c = 0.5
    CHECK(paper_sigma_s(128, 0, p) == 0.5);
    CHECK(paper_sigma_a(128, 0, p) == Approx(0.05).epsilon(1e-15));
    // level 0 -> v_c = 0; level 255 -> v_c = 255/256
    CHECK(paper_sigma_s(0, 1, p) == 0.0);
    CHECK(paper_sigma_a(0, 0, p) == Approx(0.1).epsilon(1e-15));
    CHECK(paper_sigma_s(255, 2, p) == 255.0 / 256.0);
    CHECK(paper_sigma_a(255, 0, p) == Approx(0.1 / 256.0).epsilon(1e-12));

    p.ds = 2.0;
    p.da = 0.3;
    p.ks = {0.25, -0.1, 0.0};
    CHECK(paper_sigma_s(64, 0, p) == Approx(0.25 * 2.0 + 0.25));
    CHECK(paper_sigma_s(64, 1, p) == Approx(0.25 * 2.0 - 0.1));
    CHECK(paper_sigma_a(64, 0, p) == Approx(0.75 * 2.0 * 0.3));
}

TEST_CASE("the contrasted levels' spread: g times the levels' own until they clip, then the clipped uniform's",
          "[material_volume]") {
    // Every level once: v uniform on [0, 1) in steps of 1/256, its mean
    // 255/512. Unclipped, the spread is g times the uniform's 1/√12. Past
    // g = 1 the share 1/g stays uniform on [0, 1] and the rest sits at 0 and
    // 1 half each: variance 1/4 − 1/(6g), and d ln σ / d ln g =
    // (1/(6g)) / (2 (1/4 − 1/(6g))), a quarter at g = 2 (to the grid of
    // 256 levels).
    std::vector<Rgb8> levels;
    for (int l = 0; l < 256; ++l) levels.push_back({std::uint8_t(l), std::uint8_t(l), std::uint8_t(l)});
    const LevelHistograms h = level_histograms(levels);
    OpticalParams p;
    p.mean_level = mean_levels(levels);
    const double own = std::sqrt((256.0 * 256.0 - 1.0) / 12.0) / 256.0;  // the discrete uniform's
    for (double g : {0.25, 0.5, 0.9}) {
        p.contrast = {g, g, g};
        CHECK(contrasted_spread(h, 0, p) == Approx(g * own).epsilon(1e-9));
        CHECK(contrasted_spread_elasticity(h, 1, p) == Approx(1.0).epsilon(1e-6));
    }
    for (double g : {2.0, 4.0, 8.0}) {
        p.contrast = {g, g, g};
        const double var = 0.25 - 1.0 / (6.0 * g);
        CHECK(contrasted_spread(h, 0, p) == Approx(std::sqrt(var)).epsilon(0.01));
        CHECK(contrasted_spread_elasticity(h, 2, p) == Approx(1.0 / (6.0 * g) / (2.0 * var)).epsilon(0.05));
    }
    // A volume of one level spreads nothing at any contrast.
    const LevelHistograms flat = level_histograms({{90, 90, 90}, {90, 90, 90}});
    p.contrast = {4.0, 4.0, 4.0};
    CHECK(contrasted_spread(flat, 0, p) == 0.0);
}

TEST_CASE("the contrast stretches the levels about their mean and clips them to [0, 1]", "[material_volume]") {
    OpticalParams p;
    p.mean_level = {0.5, 0.25, 0.5};
    p.contrast = {2.0, 3.0, 0.0};
    CHECK(contrasted_level(160, 0, p) == Approx(0.75));   // 0.5 + 2 (0.625 - 0.5)
    CHECK(contrasted_level(224, 0, p) == 1.0);            // 0.5 + 2 (0.875 - 0.5) clipped
    CHECK(contrasted_level(32, 0, p) == 0.0);             // 0.5 + 2 (0.125 - 0.5) clipped
    CHECK(contrasted_level(96, 1, p) == Approx(0.625));  // 0.25 + 3 (0.375 - 0.25)
    CHECK(contrasted_level(17, 2, p) == 0.5);             // contrast 0: the mean level everywhere
    p.contrast = {1.0, 1.0, 1.0};
    CHECK(contrasted_level(17, 2, p) == 17 / 256.0);      // contrast 1: the paper's level, exactly
    p.contrast = {2.0, 1.0, 1.0};
    p.extinction = Extinction::Paper;
    p.ds = 1.0, p.da = 0.5, p.ks = {0.1, 0.0, 0.0};
    CHECK(paper_sigma_s(160, 0, p) == Approx(0.75 + 0.1));
    CHECK(paper_sigma_a(160, 0, p) == Approx(0.25 * 0.5));
    // The mean level of a volume's voxels.
    const auto m = mean_levels({{0, 64, 255}, {128, 64, 1}});
    CHECK(m[0] == Approx(64 / 256.0));
    CHECK(m[1] == Approx(64 / 256.0));
    CHECK(m[2] == Approx(128 / 256.0));
}

TEST_CASE("sigma_s is clamped at zero, sigma_a is not touched by k_s", "[material_volume]") {
    OpticalParams p;
    p.extinction = Extinction::Paper;
    p.da = 0.1;
    p.ks = {-0.3, -0.3, -0.3};
    CHECK(paper_sigma_s(0, 0, p) == 0.0);
    CHECK(paper_sigma_s(64, 0, p) == 0.0);   // 0.25 - 0.3 < 0
    CHECK(paper_sigma_s(128, 0, p) == Approx(0.2));
    CHECK(paper_sigma_a(64, 0, p) == Approx(0.075));
}

TEST_CASE("a grey extinction keeps §5.1's albedo and gives every voxel and channel the extinction d_s",
          "[material_volume]") {
    OpticalParams grey, paper;
    paper.extinction = Extinction::Paper;
    // At k_s = 0 and d_a = 1, §5.1's extinction is d_s already: the same coefficients.
    for (int level : {0, 1, 100, 255})
        for (int c = 0; c < 3; ++c) {
            CHECK(paper_sigma_s(level, c, grey) == Approx(paper_sigma_s(level, c, paper)).epsilon(1e-12));
            CHECK(paper_sigma_a(level, c, grey) == Approx(paper_sigma_a(level, c, paper)).epsilon(1e-12));
        }
    for (OpticalParams* p : {&grey, &paper}) {
        p->ds = 1.5, p->da = 0.4, p->ks = {2.0, 0.5, -0.2};
        p->contrast = {3.0, 1.0, 2.0}, p->mean_level = {0.4, 0.5, 0.6};
    }
    for (int level = 0; level < 256; ++level)
        for (int c = 0; c < 3; ++c) {
            const double s = paper_sigma_s(level, c, grey), a = paper_sigma_a(level, c, grey);
            CHECK(s + a == Approx(1.5).epsilon(1e-12));
            const double ps = paper_sigma_s(level, c, paper), pa = paper_sigma_a(level, c, paper);
            CHECK(s / (s + a) == Approx(ps / (ps + pa)).margin(1e-12));
        }
    // Where k_s empties σ_s (v'·d_s + k_s < 0) the voxel only absorbs.
    CHECK(paper_sigma_s(10, 2, grey) == 0.0);
    CHECK(paper_sigma_a(10, 2, grey) == Approx(1.5));
    // Worked by hand: level 128 in green (v' = 0.5): §5.1 gives σ_s = 0.75 + 0.5,
    // σ_a = 0.5·1.5·0.4 = 0.3, so the albedo is 1.25 / 1.55.
    CHECK(paper_sigma_s(128, 1, grey) == Approx(1.5 * 1.25 / 1.55));
    CHECK(to_string(parse_extinction("grey")) == std::string("grey"));
    CHECK(parse_extinction("paper") == Extinction::Paper);
    CHECK_THROWS(parse_extinction("gray-ish"));
}

TEST_CASE("world coefficients are paper coefficients times density_scale / cube side",
          "[material_volume]") {
    OpticalParams p;
    p.density_scale = 30.0;
    const CoefficientTable t(p, 2.0);
    for (int level : {0, 77, 255}) {
        CHECK(t.sigma_s[1][level] == Approx(paper_sigma_s(level, 1, p) * 15.0).epsilon(1e-6));
        CHECK(t.sigma_a[2][level] == Approx(paper_sigma_a(level, 2, p) * 15.0).epsilon(1e-6));
    }
}

TEST_CASE("bad optical parameters are rejected", "[material_volume]") {
    OpticalParams p;
    p.ds = 0;
    CHECK_THROWS(p.validate());
    p = OpticalParams{};
    p.da = -0.1;
    CHECK_THROWS(p.validate());
    p = OpticalParams{};
    p.density_scale = 0;
    CHECK_THROWS(p.validate());
}

TEST_CASE("the volume build is the same with one and with two threads", "[material_volume]") {
    Photo photo;
    photo.width = 16;
    photo.height = 16;
    for (int i = 0; i < 256; ++i) {
        photo.levels.push_back({std::uint8_t(i), std::uint8_t(255 - i), std::uint8_t(i / 2)});
        photo.foreground.push_back(1);
    }
    NoiseParams n;
    n.resolution = 40;
    std::vector<Rgb8> one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = build_material_volume(photo, n, MatchMode::Joint, OpticalParams{}).levels;
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = build_material_volume(photo, n, MatchMode::Joint, OpticalParams{}).levels;
    }
    CHECK(one == two);
    CHECK(one.size() == 40u * 40u * 40u);
}
