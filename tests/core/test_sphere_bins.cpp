// The equal-area bins of the light guide against geometry: the octahedral
// map and its inverse undo each other, uniform directions (drawn by the
// textbook z-and-φ method, not by the map) fill every bin alike, and a
// direction drawn in a bin lies in it.

#include "jade/core/random.h"
#include "jade/core/sphere_bins.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

using namespace jade;

TEST_CASE("the equal-area map and its inverse undo each other", "[sphere_bins]") {
    for (int j = 1; j < 64; ++j)
        for (int i = 1; i < 64; ++i) {
            const glm::vec2 p(i / 64.f, j / 64.f);
            const glm::vec3 d = equal_area_square_to_sphere(p);
            INFO(p.x << ", " << p.y);
            CHECK(glm::length(d) == Approx(1.f).margin(1e-5));
            const glm::vec2 q = equal_area_sphere_to_square(d);
            CHECK(q.x == Approx(p.x).margin(1e-4));
            CHECK(q.y == Approx(p.y).margin(1e-4));
        }
}

TEST_CASE("uniform directions fill the bins alike and a bin's directions lie in it", "[sphere_bins]") {
    const SphereBins bins;
    CHECK(bins.solid_angle() * bins.count() == Approx(4.0 * 3.14159265358979).epsilon(1e-6));
    SplitMix64 rng(7);
    const int n = 2000000;
    std::vector<int> counts(std::size_t(bins.count()), 0);
    for (int k = 0; k < n; ++k) {
        const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * 3.14159265358979 * rng.uniform();
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        ++counts[std::size_t(bins.index({float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)}))];
    }
    // Each count is binomial(n, 1/count): within 5 standard deviations.
    const double expected = double(n) / bins.count(), sd = std::sqrt(expected * (1.0 - 1.0 / bins.count()));
    int worst = 0;
    for (int c : counts) worst = std::max(worst, int(std::abs(c - expected)));
    INFO("expected " << expected << " per bin, largest deviation " << worst);
    CHECK(worst < 5.0 * sd);
    int outside = 0;
    for (int b = 0; b < bins.count(); ++b)
        for (int k = 0; k < 50; ++k) {
            const float u1 = 0.001f + 0.998f * float(rng.uniform()), u2 = 0.001f + 0.998f * float(rng.uniform());
            outside += bins.index(bins.direction(b, u1, u2)) != b;
        }
    CHECK(outside == 0);
}
