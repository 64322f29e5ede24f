// The majorant grid and the tracker that walks it: segments that tile a ray
// and bound every lookup in them, cells no looser than the voxels they can
// read, and tracking over the cells (with flights cut into stretches, as the
// boundary's clearance cuts them) that reproduces the optical depth the
// grid's own lookups integrate to.

#include "jade/render/majorant_grid.h"
#include "jade/render/media/grid.h"
#include "jade/render/tracking.h"
#include "jade/core/random.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace jade;

namespace {

// A grid of random coefficients whose extinction spans two orders of
// magnitude, so a global majorant would make most collisions null.
CoefficientGrids random_grids(std::array<int, 3> size, std::uint64_t seed) {
    CoefficientGrids g;
    g.placement.size = size;
    g.placement.origin = glm::vec3(-0.3f, 0.1f, -0.2f);
    g.placement.spacing = glm::vec3(0.1f, 0.07f, 0.13f);
    SplitMix64 rng(seed);
    for (std::size_t i = 0; i < g.placement.voxels(); ++i) {
        const float scale = 0.1f * float(std::pow(10.0, 2.0 * rng.uniform()));
        g.sigma_s.push_back(scale * Spectrum(float(rng.uniform()), float(rng.uniform()), float(rng.uniform())));
        g.sigma_a.push_back(scale * Spectrum(float(rng.uniform()), 0.f, float(rng.uniform())));
    }
    return g;
}

Spectrum sigma_t(const Medium& m, const glm::vec3& p) {
    const MediumProperties mp = m.at(p);
    return mp.sigma_s + mp.sigma_a;
}

// ∫ σ_t along o + t·d for t in [0, t_end], by the midpoint rule over steps
// far finer than a voxel (the lookup is continuous and piecewise smooth).
Spectrum optical_depth(const Medium& m, const glm::vec3& o, const glm::vec3& d, float t_end) {
    const int n = 20000;
    const double dt = double(t_end) / n;
    double tau[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
        const Spectrum s = sigma_t(m, o + float((i + 0.5) * dt) * d);
        for (int c = 0; c < 3; ++c) tau[c] += s[c] * dt;
    }
    return Spectrum(float(tau[0]), float(tau[1]), float(tau[2]));
}

}  // namespace

TEST_CASE("the majorant grid's segments tile the ray and bound every lookup in them", "[medium]") {
    const FloatGridMedium medium(random_grids({13, 9, 7}, 3));
    const MajorantGrid& grid = *medium.majorant_grid();
    CHECK(grid.cells() == std::array<int, 3>{3, 2, 2});  // (size − 1) / 4, rounded up
    SampleStream u(7, 1, 2);
    int segments = 0;
    for (int ray = 0; ray < 2000; ++ray) {
        // Origins inside the grid and up to half its size outside it (where
        // lookups clamp to the edge), some directions along an axis.
        const glm::vec3 o(u.uniform() * 2.4f - 0.9f, u.uniform() * 1.2f - 0.3f, u.uniform() * 1.6f - 0.7f);
        glm::vec3 d(u.uniform() - 0.5f, u.uniform() - 0.5f, u.uniform() - 0.5f);
        if (ray % 5 == 0) d[ray / 5 % 3] = 0.f;
        d = glm::normalize(d);
        // Walked in up to three stretches, as the clearance cuts a flight.
        MajorantIterator it(&grid, medium.majorant(), o, d);
        float end = 0.f;
        const float t_to[3] = {u.uniform() * 0.5f, 0.5f + u.uniform() * 0.5f, 2.5f};
        for (float stop : t_to) {
            for (MajorantSegment seg; it.next(seg, stop);) {
                ++segments;
                REQUIRE(seg.t_min == end);  // no gap, no overlap
                REQUIRE(seg.t_max > seg.t_min);
                REQUIRE(seg.t_max <= stop);
                end = seg.t_max;
                for (int k = 0; k <= 4; ++k) {
                    const float t = seg.t_min + (seg.t_max - seg.t_min) * (k < 4 ? k / 4.f : 1.f);
                    const Spectrum s = sigma_t(medium, o + t * d);
                    for (int c = 0; c < 3; ++c) REQUIRE(s[c] <= seg.sigma_maj[c] * (1.f + 1e-5f));
                }
            }
            REQUIRE(end == stop);
        }
    }
    CHECK(segments > 4 * 2000);  // the rays do cross cells
}

TEST_CASE("a majorant cell reads only the voxels within one of it", "[medium]") {
    // One dense voxel (8, 8, 8) in a 16³ grid of extinction 1. Cells of 4
    // voxels: cell c holds lookups at voxel coordinates [4c, 4c + 4] and
    // reads voxels 4c − 1 to 4c + 5 (the stencil's next voxel and one of
    // margin), so only cells 1 and 2 along each axis see voxel 8.
    CoefficientGrids g;
    g.placement.size = {16, 16, 16};
    g.placement.spacing = glm::vec3(0.5f);
    g.sigma_s.assign(g.placement.voxels(), Spectrum(1.f));
    g.sigma_a.assign(g.placement.voxels(), Spectrum(0.f));
    g.sigma_s[(8 * 16 + 8) * 16 + 8] = Spectrum(10.f, 20.f, 30.f);
    const FloatGridMedium medium(g);
    const MajorantGrid& grid = *medium.majorant_grid();
    REQUIRE(grid.cells() == std::array<int, 3>{4, 4, 4});
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                const bool sees = (i == 1 || i == 2) && (j == 1 || j == 2) && (k == 1 || k == 2);
                INFO("cell " << i << " " << j << " " << k);
                CHECK(grid.cell(i, j, k) == (sees ? Spectrum(10.f, 20.f, 30.f) : Spectrum(1.f)));
            }
    // A ray along a row of cells that never reads the dense voxel meets
    // only majorant 1: no null collision to draw.
    MajorantIterator it(&grid, medium.majorant(), glm::vec3(-3.f, 1.f, 1.f), glm::vec3(1.f, 0.f, 0.f));
    for (MajorantSegment seg; it.next(seg, 20.f);) CHECK(seg.sigma_maj == Spectrum(1.f));
}

TEST_CASE("delta tracking over the majorant grid, its flights cut into stretches, escapes with exp(-tau)",
          "[medium][integrator]") {
    // The probability that a flight drawn by channel h's majorants makes no
    // real collision before t_end is T_h = exp(−τ_h), τ the lookups'
    // optical depth (integrated independently, above). Cutting the flight
    // into stretches, where the tracker carries the drawn optical depth
    // across, must not change it.
    const FloatGridMedium medium(random_grids({12, 14, 9}, 11));
    const glm::vec3 o(-0.35f, 0.05f, -0.1f);
    const glm::vec3 d = glm::normalize(glm::vec3(1.f, 0.6f, 0.8f));
    const float t_end = 1.2f;
    const Spectrum tau = optical_depth(medium, o, d, t_end);
    INFO("optical depth " << tau.x << " " << tau.y << " " << tau.z);
    for (int c = 0; c < 3; ++c) REQUIRE((tau[c] > 0.3f && tau[c] < 4.f));  // neither all nor none escape
    const int n = 60000;
    for (int h = 0; h < 3; ++h) {
        for (int stretches : {1, 3}) {
            int escaped = 0;
            std::uint64_t tentative = 0;
            for (int i = 0; i < n; ++i) {
                SampleStream rng(21, std::uint64_t(h * 10 + stretches), std::uint64_t(i));
                MajorantTracker tracker(medium, o, d, h, Spectrum(0.f));
                bool collided = false;
                for (int k = 1; k <= stretches && !collided; ++k) {
                    const float stop = k == stretches ? t_end : t_end * rng.uniform();
                    tracker.track_to(std::max(stop, 0.f), rng,
                                     [&](const glm::vec3&, const MediumProperties& m, const Spectrum& mu,
                                         const Spectrum&) {
                                         ++tentative;
                                         collided = rng.uniform() < (m.sigma_s[h] + m.sigma_a[h]) / mu[h];
                                         return !collided;
                                     });
                }
                if (!collided) ++escaped;
            }
            const double p = std::exp(-double(tau[h])), se = std::sqrt(p * (1 - p) / n);
            INFO("channel " << h << ", " << stretches << " stretches: " << double(escaped) / n << " vs " << p);
            CHECK(std::abs(double(escaped) / n - p) < 5.0 * se);
            // Local majorants keep most tentative collisions real: fewer
            // than the global majorant's optical depth would draw.
            CHECK(double(tentative) / n < medium.majorant()[h] * t_end);
        }
    }
}

TEST_CASE("residual ratio tracking over the majorant grid matches the optical depth per channel", "[medium][integrator]") {
    const FloatGridMedium medium(random_grids({12, 14, 9}, 12));
    const glm::vec3 o(0.9f, 1.1f, 1.0f);
    const glm::vec3 d = glm::normalize(glm::vec3(-1.f, -0.9f, -0.7f));
    const float t_end = 1.3f;
    const Spectrum tau = optical_depth(medium, o, d, t_end);
    INFO("optical depth " << tau.x << " " << tau.y << " " << tau.z);
    for (int c = 0; c < 3; ++c) REQUIRE((tau[c] > 0.3f && tau[c] < 4.f));
    PathCounters counters;
    double sum[3] = {0, 0, 0}, sum_sq[3] = {0, 0, 0};
    const int n = 60000;
    for (int i = 0; i < n; ++i) {
        SampleStream rng(22, 0, std::uint64_t(i));
        const Spectrum t = ratio_tracking(medium, o, d, t_end, rng, counters);
        for (int c = 0; c < 3; ++c) {
            sum[c] += t[c];
            sum_sq[c] += double(t[c]) * t[c];
        }
    }
    for (int c = 0; c < 3; ++c) {
        const double mean = sum[c] / n, var = (sum_sq[c] / n - mean * mean) / (n - 1);
        const double expect = std::exp(-double(tau[c]));
        INFO("channel " << c << ": " << mean << " vs " << expect << " (standard error " << std::sqrt(var) << ")");
        CHECK(std::abs(mean - expect) < 5.0 * std::sqrt(var) + 1e-4 * expect);
    }
}
