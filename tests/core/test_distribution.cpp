// Piecewise-constant densities: exact values of a small 1-D case (worked by
// hand), the all-zero fallback, and a 2-D density that integrates to one
// and whose samples carry the density pdf() gives their point.

#include "jade/core/distribution.h"
#include "jade/core/random.h"

#include <catch2/catch.hpp>

using namespace jade;

TEST_CASE("a 1-D piecewise-constant density is inverted exactly", "[distribution]") {
    // Values 1, 0, 3 on thirds of [0, 1): integral 4/3, densities 0.75, 0, 2.25,
    // cumulative 0, 0.25, 0.25, 1.
    const PiecewiseConstant1D d({1.f, 0.f, 3.f});
    CHECK(d.integral() == Approx(4.0 / 3.0));
    float pdf;
    int piece;
    float x = d.sample(0.1f, pdf, piece);
    CHECK(piece == 0);
    CHECK(pdf == Approx(0.75f));
    CHECK(x == Approx(0.1 / 0.25 / 3.0));
    x = d.sample(0.5f, pdf, piece);
    CHECK(piece == 2);
    CHECK(pdf == Approx(2.25f));
    CHECK(x == Approx((2.0 + 1.0 / 3.0) / 3.0));
    CHECK(d.pdf(0.5f) == 0.f);  // the empty piece is never drawn
    for (float u = 0.f; u < 1.f; u += 1.f / 1024.f) {
        d.sample(u, pdf, piece);
        REQUIRE(piece != 1);
    }
    CHECK(d.sample(0.9999999f, pdf, piece) < 1.f);
}

TEST_CASE("an all-zero 1-D density is uniform", "[distribution]") {
    const PiecewiseConstant1D d({0.f, 0.f, std::nanf(""), -1.f});
    float pdf;
    int piece;
    CHECK(d.sample(0.6f, pdf, piece) == Approx(0.6f));
    CHECK(pdf == Approx(1.f));
    CHECK(piece == 2);
}

TEST_CASE("a 2-D piecewise-constant density integrates to one and its samples carry pdf()", "[distribution]") {
    const int nx = 7, ny = 5;
    std::vector<float> v;
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) v.push_back(float((x * 3 + y * 5) % 4));  // some zeros
    const PiecewiseConstant2D d(v, nx, ny);
    double total = 0;
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
            const float p = d.pdf({(x + 0.5f) / nx, (y + 0.5f) / ny});
            // The density is proportional to the value: value / mean.
            double mean = 0;
            for (float f : v) mean += f / v.size();
            CHECK(p == Approx(v[std::size_t(y * nx + x)] / mean));
            total += p / (nx * ny);
        }
    CHECK(total == Approx(1.0));
    SampleStream rng(3, 4, 5);
    std::vector<int> counts(v.size(), 0);
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        float pdf;
        const float u1 = rng.uniform(), u2 = rng.uniform();
        const glm::vec2 p = d.sample(u1, u2, pdf);
        REQUIRE(pdf == d.pdf(p));
        REQUIRE(pdf > 0.f);
        ++counts[std::size_t(int(p.y * ny) * nx + int(p.x * nx))];
    }
    // Each cell's count is binomial with p = pdf / (nx · ny): within 4.5 σ.
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
            const double p = d.pdf({(x + 0.5f) / nx, (y + 0.5f) / ny}) / (nx * ny);
            const double sigma = std::sqrt(n * p * (1 - p));
            CHECK(std::abs(counts[std::size_t(y * nx + x)] - n * p) <= 4.5 * sigma);
        }
}
