// Media: trilinear lookup between voxel centres with clamped edges (the
// OpenVDB / Mitsuba convention of the reference scene C), majorants and
// minorants that bound every lookup, and the material volume's coefficients per cube.

#include "jade/render/media/grid.h"
#include "jade/render/media/homogeneous.h"
#include "jade/core/random.h"

#include <catch2/catch.hpp>

using namespace jade;

namespace {
// A 3x2x2 grid whose σ_s is a linear function of the voxel index, so the
// trilinear interpolant between centres is that same linear function.
CoefficientGrids linear_grids() {
    CoefficientGrids g;
    g.placement.size = {3, 2, 2};
    g.placement.origin = glm::vec3(-1.f, 0.f, 2.f);
    g.placement.spacing = glm::vec3(0.5f, 1.f, 2.f);
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
                g.sigma_s.push_back(Spectrum(1.f + i, 2.f * j, 3.f * k));
                g.sigma_a.push_back(Spectrum(0.5f));
            }
    return g;
}
}  // namespace

TEST_CASE("grid lookup is trilinear between voxel centres and clamped outside", "[medium]") {
    const FloatGridMedium m(linear_grids());
    // Voxel centres return their own values.
    CHECK(m.at({-1.f, 0.f, 2.f}).sigma_s == Spectrum(1.f, 0.f, 0.f));
    CHECK(m.at({0.f, 1.f, 4.f}).sigma_s == Spectrum(3.f, 2.f, 3.f));
    // Between centres: the linear function.
    const MediumProperties mid = m.at({-0.625f, 0.25f, 3.5f});  // index (0.75, 0.25, 0.75)
    CHECK(mid.sigma_s.x == Approx(1.75f));
    CHECK(mid.sigma_s.y == Approx(0.5f));
    CHECK(mid.sigma_s.z == Approx(2.25f));
    CHECK(mid.sigma_a.x == Approx(0.5f));
    // Beyond the last centre the edge value extends (clamp), on every side.
    CHECK(m.at({5.f, -3.f, 0.f}).sigma_s == Spectrum(3.f, 0.f, 0.f));
    CHECK(m.at({-9.f, 9.f, 9.f}).sigma_s == Spectrum(1.f, 2.f, 3.f));
    CHECK(m.majorant() == Spectrum(3.5f, 2.5f, 3.5f));
    CHECK(m.minorant() == Spectrum(1.5f, 0.5f, 0.5f));
}

TEST_CASE("the majorant and the minorant bound the extinction everywhere", "[medium]") {
    CoefficientGrids g;
    g.placement.size = {5, 4, 3};
    g.placement.spacing = glm::vec3(0.1f);
    SplitMix64 rng(5);
    for (std::size_t i = 0; i < g.placement.voxels(); ++i) {
        g.sigma_s.push_back(Spectrum(float(rng.uniform() * 10), float(rng.uniform()), float(rng.uniform() * 3)));
        g.sigma_a.push_back(Spectrum(float(rng.uniform()), 0.f, float(rng.uniform() * 7)));
    }
    const FloatGridMedium m(g);
    SampleStream u(1, 2, 3);
    for (int i = 0; i < 20000; ++i) {
        const glm::vec3 p(u.uniform() * 0.7f - 0.1f, u.uniform() * 0.6f - 0.1f, u.uniform() * 0.5f - 0.1f);
        const MediumProperties mp = m.at(p);
        for (int c = 0; c < 3; ++c) {
            REQUIRE(mp.sigma_s[c] + mp.sigma_a[c] <= m.majorant()[c] * (1 + 1e-6f));
            REQUIRE(mp.sigma_s[c] + mp.sigma_a[c] >= m.minorant()[c] * (1 - 1e-6f));
        }
    }
    for (int c = 0; c < 3; ++c) CHECK(m.minorant()[c] > 0.f);  // channel 1's σ_a is 0, its σ_s is not
}

TEST_CASE("negative or non-finite coefficients are refused", "[medium]") {
    CHECK_THROWS(HomogeneousMedium(Spectrum(-1.f), Spectrum(0.f)));
    CoefficientGrids g = linear_grids();
    g.sigma_a[4] = Spectrum(std::nanf(""));
    CHECK_THROWS(FloatGridMedium(g));
}

TEST_CASE("a grey extinction makes the material volume's extinction one number", "[medium]") {
    MaterialVolume v;
    v.resolution = 4;
    v.levels.assign(64, Rgb8{128, 64, 255});
    v.levels[v.index(3, 3, 3)] = Rgb8{0, 30, 7};
    v.optics.ks = {2.0, 0.5, -0.1};  // §5.1 would give each channel its own extinction
    v.optics.contrast = {3.0, 2.0, 1.0};
    v.optics.mean_level = {0.4, 0.3, 0.6};
    Cube cube;
    cube.min = {0.0, 0.0, 0.0};
    cube.side = 0.5;
    const MaterialVolumeMedium m(v, cube);
    const float sigma_t = float(v.optics.ds * v.optics.density_scale / cube.side);
    for (int c = 0; c < 3; ++c) {
        CHECK(m.majorant()[c] == Approx(sigma_t).epsilon(1e-6));
        CHECK(m.minorant()[c] == Approx(sigma_t).epsilon(1e-6));
    }
    const MediumProperties p = m.at({0.0625f, 0.0625f, 0.0625f});
    CHECK(p.sigma_s.x / sigma_t == Approx((0.4 + 3.0 * (0.5 - 0.4) + 2.0) / (0.7 + 2.0 + 0.3)));
}

TEST_CASE("the material volume becomes world coefficients on any cube", "[medium]") {
    MaterialVolume v;
    v.resolution = 4;
    v.levels.assign(64, Rgb8{128, 64, 255});
    v.levels[v.index(3, 3, 3)] = Rgb8{0, 0, 0};
    v.optics.ks = {0.1, 0.0, -0.2};
    v.optics.da = 0.1;  // the paper's d_a and extinction, as in the numbers below
    v.optics.extinction = Extinction::Paper;
    for (double side : {1.0, 0.25}) {
        Cube cube;
        cube.min = {2.0, -1.0, 0.0};
        cube.side = side;
        const MaterialVolumeMedium m(v, cube);
        const double h = side / 4;
        // Centre of voxel (0, 0, 0): σ_s = (v_c d_s + k_s) · density_scale / side (§5.1; docs/design.md, "Units").
        const MediumProperties p = m.at({float(2.0 + h / 2), float(-1.0 + h / 2), float(h / 2)});
        const double scale = v.optics.density_scale / side;
        CHECK(p.sigma_s.x == Approx((128 / 256.0 + 0.1) * scale));
        CHECK(p.sigma_s.y == Approx((64 / 256.0) * scale));
        CHECK(p.sigma_s.z == Approx((255 / 256.0 - 0.2) * scale));
        CHECK(p.sigma_a.x == Approx((1 - 128 / 256.0) * 0.1 * scale));
        // The optical thickness across the cube is the same for every cube size.
        CHECK(p.sigma_s.x * side == Approx((128 / 256.0 + 0.1) * v.optics.density_scale));
        // The majorant covers the largest level that occurs (the sigma_a of
        // level 0), the minorant the smallest.
        CHECK(m.majorant().x == Approx(std::max((128 / 256.0 + 0.1) + 0.5 * 0.1, 0.1 + 0.1) * scale));
        CHECK(m.minorant().x == Approx(std::min((128 / 256.0 + 0.1) + 0.5 * 0.1, 0.1 + 0.1) * scale));
    }
}
