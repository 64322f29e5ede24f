// The dimensions a pixel's samples share: each sample's value must be
// uniform on its own (else every sample is biased), and a pixel's samples
// must cover the dimension evenly (else nothing is gained).

#include "jade/core/random.h"
#include "jade/render/pixel_sampler.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <vector>

using namespace jade;

TEST_CASE("stratified heroes: every three consecutive samples of a pixel take each channel once",
          "[pixel_sampler]") {
    for (std::uint64_t pixel = 0; pixel < 500; ++pixel)
        for (std::uint64_t first = 0; first < 40; ++first) {
            std::array<int, 3> seen{0, 0, 0};
            for (std::uint64_t k = 0; k < 3; ++k) {
                const int h = stratified_hero(7, pixel, first + k);
                REQUIRE(h >= 0);
                REQUIRE(h <= 2);
                ++seen[std::size_t(h)];
            }
            CHECK(seen == std::array<int, 3>{1, 1, 1});
        }
}

TEST_CASE("stratified heroes: a sample's hero is uniform over pixels and depends only on its key",
          "[pixel_sampler]") {
    // 30 000 pixels: each channel's count of sample 5's hero is binomial
    // (n 30 000, p 1/3), standard deviation 81.6; 5 of them allowed.
    const int n = 30000;
    std::array<int, 3> count{0, 0, 0};
    int differ = 0;
    for (int pixel = 0; pixel < n; ++pixel) {
        const int h = stratified_hero(11, std::uint64_t(pixel), 5);
        ++count[std::size_t(h)];
        CHECK(stratified_hero(11, std::uint64_t(pixel), 5) == h);  // a pass split elsewhere draws the same
        differ += stratified_hero(12, std::uint64_t(pixel), 5) != h ? 1 : 0;
    }
    const double sd = std::sqrt(n * (1.0 / 3.0) * (2.0 / 3.0));
    for (int c : count) CHECK(std::abs(c - n / 3.0) < 5.0 * sd);
    // Another seed draws other starts: two thirds of the pixels differ.
    CHECK(std::abs(differ - 2.0 * n / 3.0) < 5.0 * sd);
}

namespace {

// The sample index of point j of replicate r, hero turn position k (0–2).
std::uint64_t sample_of(std::uint64_t j, int r, int k) {
    return 3 * (j * kReplicates + std::uint64_t(r)) + std::uint64_t(k);
}

// Whether 2^k points of the unit square hold 2^t in every elementary
// interval of area 2^(t−k): a (t, k, 2)-net in base 2.
bool is_net(const std::vector<std::array<float, 2>>& points, int k, int t) {
    for (int a = 0; a <= k - t; ++a) {
        const int b = k - t - a;  // intervals of 2^-a by 2^-b
        std::vector<int> count(std::size_t(1) << (a + b), 0);
        for (const auto& p : points)
            ++count[(std::size_t(p[0] * float(1 << a)) << b) | std::size_t(p[1] * float(1 << b))];
        for (int c : count)
            if (c != 1 << t) return false;
    }
    return true;
}

// The correlation between x(i) and y(i) over i < n.
double correlation(int n, const std::function<double(std::size_t)>& x, const std::function<double(std::size_t)>& y) {
    double sxy = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0;
    for (int i = 0; i < n; ++i) {
        const double a = x(std::size_t(i)), b = y(std::size_t(i));
        sx += a, sy += b, sxy += a * b, sxx += a * a, syy += b * b;
    }
    const double cov = sxy / n - sx / n * sy / n;
    return cov / std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
}

}  // namespace

TEST_CASE("replicates: every turn of the heroes lies in one replicate and shares its first numbers",
          "[pixel_sampler]") {
    for (std::uint64_t s = 0; s < 300; ++s) {
        CHECK(sample_replicate(s) == int((s / 3) % kReplicates));
        const FirstNumbers u = first_numbers(3, 17, s), turn = first_numbers(3, 17, s - s % 3);
        CHECK(u.flight == turn.flight);
        CHECK(u.direction == turn.direction);
    }
}

TEST_CASE("replicates: each replicate's first 2^k flight numbers keep one in each interval of width 2^-k",
          "[pixel_sampler]") {
    // The van der Corput sequence is a (0, 1)-sequence in base 2 and Owen's
    // scrambling permutes dyadic intervals whole: for every k up to 10 and
    // every prefix of 2^k points, each interval of width 2^-k holds one.
    for (std::uint64_t pixel : {0ull, 1ull, 977ull})
        for (int r = 0; r < kReplicates; ++r)
            for (int k = 0; k <= 10; ++k) {
                const int n = 1 << k;
                std::vector<int> per_interval(std::size_t(n), 0);
                for (std::uint64_t j = 0; j < std::uint64_t(n); ++j) {
                    const float u = first_numbers(5, pixel, sample_of(j, r, 2)).flight;
                    REQUIRE(u >= 0.f);
                    REQUIRE(u < 1.f);
                    REQUIRE(u * 16777216.f == std::floor(u * 16777216.f));  // a multiple of 2^-24
                    ++per_interval[std::size_t(u * float(n))];
                }
                for (int count : per_interval) CHECK(count == 1);
            }
}

TEST_CASE("replicates: a flight number is uniform over pixels and independent between replicates",
          "[pixel_sampler]") {
    // 16 000 pixels: each of 16 bins of sample 40's number is binomial
    // (n 16 000, p 1/16), standard deviation 30.6; 5 of them allowed. The
    // correlation between two replicates' numbers, and between a number and
    // the first of the sample's own stream, has standard deviation
    // 1/√16 000 = 0.0079 over the pixels; 5 of them allowed.
    const int n = 16000;
    std::array<int, 16> bins{};
    const auto with_flight = [&](const std::function<double(std::size_t)>& other) {
        return correlation(n, [](std::size_t p) { return double(first_numbers(9, p, 40).flight); }, other);
    };
    for (int pixel = 0; pixel < n; ++pixel) ++bins[std::size_t(first_numbers(9, std::uint64_t(pixel), 40).flight * 16.f)];
    const double sd = std::sqrt(n * (1.0 / 16.0) * (15.0 / 16.0));
    for (int b : bins) CHECK(std::abs(b - n / 16.0) < 5.0 * sd);
    REQUIRE(sample_replicate(40) != sample_replicate(43));
    CHECK(std::abs(with_flight([](std::size_t p) { return double(first_numbers(9, p, 43).flight); })) <
          5.0 / std::sqrt(double(n)));
    CHECK(std::abs(with_flight([](std::size_t p) { return double(SampleStream(9, p, 40).uniform()); })) <
          5.0 / std::sqrt(double(n)));
}

namespace {

// The first 2^k points of replicate r in dimensions x and y of (flight,
// direction[0], direction[1]).
std::vector<std::array<float, 2>> first_points(std::uint64_t pixel, int r, int k, int x, int y) {
    std::vector<std::array<float, 2>> points;
    for (std::uint64_t j = 0; j < (1ull << k); ++j) {
        const FirstNumbers u = first_numbers(5, pixel, sample_of(j, r, 1));
        const std::array<float, 3> p{u.flight, u.direction[0], u.direction[1]};
        points.push_back({p[std::size_t(x)], p[std::size_t(y)]});
    }
    return points;
}

bool is_net(std::uint64_t pixel, int r, int k, int t, int x, int y) {
    return is_net(first_points(pixel, r, k, x, y), k, t);
}

}  // namespace

TEST_CASE("replicates: a replicate's first numbers are Sobol' nets in the flight and the direction",
          "[pixel_sampler]") {
    // Sobol's first two dimensions are a (0, 2)-sequence, and its first and
    // third, and second and third, (1, 2)-sequences (Joe & Kuo 2008); Owen's
    // scrambling keeps a net a net. So every prefix of 2^k points of a
    // replicate holds one point in each elementary interval of area 2^-k in
    // (flight, first direction number), and two in each of area 2^(1−k) in
    // the other two pairs. A net of the wrong generator, or scrambles that
    // broke intervals, fails (the direction's numbers with each other hold
    // no (0, k, 2)-net from k = 2 on).
    for (std::uint64_t pixel : {0ull, 1ull, 977ull})
        for (int r = 0; r < kReplicates; ++r)
            for (int k = 1; k <= 9; ++k) {
                CHECK(is_net(pixel, r, k, 0, 0, 1));
                CHECK(is_net(pixel, r, k, 1, 1, 2));
                CHECK(is_net(pixel, r, k, 1, 0, 2));
            }
    CHECK_FALSE(is_net(0, 0, 4, 0, 1, 2));
}

TEST_CASE("replicates: the direction's numbers are uniform over pixels and independent of each other and the flight's",
          "[pixel_sampler]") {
    // 16 000 pixels, sample 40: each of 4 × 4 bins of the two direction
    // numbers is binomial (n 16 000, p 1/16), standard deviation 30.6; 5 of
    // them allowed. The correlations between the three numbers of one
    // sample, and with the other replicate's, have standard deviation
    // 1/√16 000 over the pixels; 5 of them allowed.
    const int n = 16000;
    std::array<int, 16> bins{};
    std::vector<FirstNumbers> u, v;
    for (int pixel = 0; pixel < n; ++pixel) {
        u.push_back(first_numbers(9, std::uint64_t(pixel), 40));
        v.push_back(first_numbers(9, std::uint64_t(pixel), 43));
        ++bins[std::size_t(u.back().direction[0] * 4.f) * 4 + std::size_t(u.back().direction[1] * 4.f)];
    }
    const double sd = std::sqrt(n * (1.0 / 16.0) * (15.0 / 16.0));
    for (int b : bins) CHECK(std::abs(b - n / 16.0) < 5.0 * sd);
    const double bound = 5.0 / std::sqrt(double(n));
    const auto flight = [&](std::size_t i) { return double(u[i].flight); };
    const auto d0 = [&](std::size_t i) { return double(u[i].direction[0]); };
    const auto d1 = [&](std::size_t i) { return double(u[i].direction[1]); };
    CHECK(std::abs(correlation(n, flight, d0)) < bound);
    CHECK(std::abs(correlation(n, flight, d1)) < bound);
    CHECK(std::abs(correlation(n, d0, d1)) < bound);
    CHECK(std::abs(correlation(n, d0, [&](std::size_t i) { return double(v[i].direction[0]); })) < bound);
    CHECK(std::abs(correlation(n, d1, [&](std::size_t i) { return double(v[i].direction[1]); })) < bound);
}

namespace {

// The sample index of a replicate's n-th film position (its turns' samples
// in order).
std::uint64_t film_sample_of(std::uint64_t n, int r) { return sample_of(n / 3, r, int(n % 3)); }

// The first 2^k film positions of replicate r.
std::vector<std::array<float, 2>> film_points(std::uint64_t pixel, int r, int k) {
    std::vector<std::array<float, 2>> points;
    for (std::uint64_t i = 0; i < (1ull << k); ++i) points.push_back(film_numbers(5, pixel, film_sample_of(i, r)));
    return points;
}

}  // namespace

TEST_CASE("film positions: every prefix of a replicate's positions is a (0, k, 2)-net over the pixel",
          "[pixel_sampler]") {
    // The shuffled index maps the first 2^k positions onto an aligned block
    // of 2^k points of Sobol's first two dimensions, a (0, k, 2)-net, and
    // Owen's scrambling keeps it one.
    for (std::uint64_t pixel : {0ull, 1ull, 977ull})
        for (int r = 0; r < kReplicates; ++r)
            for (int k = 1; k <= 10; ++k) CHECK(is_net(film_points(pixel, r, k), k, 0));
    // Each sample of a turn has its own position (the first numbers are the
    // turn's), and each is a multiple of 2^-24 in [0, 1).
    for (std::uint64_t s = 0; s < 300; s += 3) {
        const auto a = film_numbers(3, 17, s), b = film_numbers(3, 17, s + 1);
        CHECK(a != b);
        for (float u : {a[0], a[1], b[0], b[1]}) {
            REQUIRE(u >= 0.f);
            REQUIRE(u < 1.f);
            CHECK(u * 16777216.f == std::floor(u * 16777216.f));
        }
    }
}

TEST_CASE("film positions: uniform over pixels and independent of the first numbers and between replicates",
          "[pixel_sampler]") {
    // 16 000 pixels, sample 40: each of 4 × 4 bins binomial (n 16 000, p
    // 1/16), standard deviation 30.6, 5 of them allowed; correlations with
    // standard deviation 1/√16 000, 5 of them allowed.
    const int n = 16000;
    std::array<int, 16> bins{};
    std::vector<std::array<float, 2>> film, other;
    std::vector<FirstNumbers> first;
    for (int pixel = 0; pixel < n; ++pixel) {
        film.push_back(film_numbers(9, std::uint64_t(pixel), 40));
        other.push_back(film_numbers(9, std::uint64_t(pixel), 43));
        first.push_back(first_numbers(9, std::uint64_t(pixel), 40));
        ++bins[std::size_t(film.back()[0] * 4.f) * 4 + std::size_t(film.back()[1] * 4.f)];
    }
    const double sd = std::sqrt(n * (1.0 / 16.0) * (15.0 / 16.0));
    for (int b : bins) CHECK(std::abs(b - n / 16.0) < 5.0 * sd);
    const double bound = 5.0 / std::sqrt(double(n));
    for (std::size_t d = 0; d < 2; ++d) {
        const auto f = [&, d](std::size_t i) { return double(film[i][d]); };
        CHECK(std::abs(correlation(n, f, [&](std::size_t i) { return double(first[i].flight); })) < bound);
        CHECK(std::abs(correlation(n, f, [&](std::size_t i) { return double(first[i].direction[0]); })) < bound);
        CHECK(std::abs(correlation(n, f, [&](std::size_t i) { return double(first[i].direction[1]); })) < bound);
        CHECK(std::abs(correlation(n, f, [&, d](std::size_t i) { return double(other[i][d]); })) < bound);
    }
    CHECK(std::abs(correlation(n, [&](std::size_t i) { return double(film[i][0]); },
                               [&](std::size_t i) { return double(film[i][1]); })) < bound);
}
