// Histograms of Table 3: proportions H, brightness A, difference D, quantiles.

#include "jade/volume/histogram.h"

#include <catch2/catch.hpp>

using namespace jade;

TEST_CASE("histogram proportions, mean A and CDF of known levels", "[histogram]") {
    const std::vector<Rgb8> px = {{0, 10, 255}, {100, 10, 255}, {100, 20, 0}, {200, 20, 0}};
    const RgbHistogram h = RgbHistogram::of(px);
    CHECK(h.total == 4);
    CHECK(h.proportion(0, 100) == 0.5);
    CHECK(h.proportion(2, 255) == 0.5);
    CHECK(h.mean(0) == Approx(100.0));       // (0 + 100 + 100 + 200) / 4
    CHECK(h.mean(1) == Approx(15.0));
    CHECK(h.mean(2) == Approx(127.5));
    const auto f = h.cdf(0);
    CHECK(f[0] == 0.25);
    CHECK(f[99] == 0.25);
    CHECK(f[100] == 0.75);
    CHECK(f[255] == 1.0);
}

TEST_CASE("quantile is the inverse of the CDF", "[histogram]") {
    const std::vector<Rgb8> px = {{0, 0, 0}, {100, 0, 0}, {100, 0, 0}, {200, 0, 0}};
    const RgbHistogram h = RgbHistogram::of(px);
    CHECK(h.quantile(0, 0.0) == 0);
    CHECK(h.quantile(0, 0.24) == 0);
    CHECK(h.quantile(0, 0.25) == 100);
    CHECK(h.quantile(0, 0.74) == 100);
    CHECK(h.quantile(0, 0.75) == 200);
    CHECK(h.quantile(0, 0.999) == 200);
}

TEST_CASE("histogram difference D is the sum of squared proportion differences", "[histogram]") {
    const RgbHistogram a = RgbHistogram::of(std::vector<Rgb8>{{10, 0, 0}, {20, 0, 0}});
    const RgbHistogram b = RgbHistogram::of(std::vector<Rgb8>{{10, 0, 0}, {10, 0, 0}});
    // level 10: 0.5 vs 1.0, level 20: 0.5 vs 0 -> 0.25 + 0.25
    CHECK(histogram_distance(a, b, 0) == Approx(0.5));
    CHECK(histogram_distance(a, a, 0) == 0.0);
    CHECK(histogram_distance(a, b, 1) == 0.0);
}
