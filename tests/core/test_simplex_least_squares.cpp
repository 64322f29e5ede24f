// Least squares over the probability simplex against closed-form minima, and
// its lower bound against every mixture tried.
#include "jade/core/simplex_least_squares.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

using namespace jade;

namespace {

double objective(const std::vector<std::vector<double>>& k, const std::vector<double>& h, const std::vector<double>& p) {
    double f = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        double r = -h[i];
        for (std::size_t j = 0; j < k.size(); ++j) r += p[j] * k[j][i];
        f += r * r;
    }
    return f;
}

// The least objective over 20 000 random mixtures, sparse (one to four
// parts, which reach near the optimum more often than dense mixtures), of
// exponential weights: `add(p, w)` lays a part of weight w into p.
template <class Add>
double least_of_random_mixtures(const std::vector<std::vector<double>>& k, const std::vector<double>& h,
                                std::mt19937& rng, Add add) {
    std::exponential_distribution<double> e(1.0);
    double least = 1e9;
    for (int t = 0; t < 20000; ++t) {
        std::vector<double> p(k.size(), 0.0);
        double sum = 0.0;
        for (int part = 0; part < 1 + t % 4; ++part) {
            const double w = e(rng);
            add(p, w);
            sum += w;
        }
        for (double& x : p) x /= sum;
        least = std::min(least, objective(k, h, p));
    }
    return least;
}

}  // namespace

TEST_CASE("projection onto the simplex", "[core][simplex]") {
    std::vector<double> inside{0.2, 0.3, 0.5};
    project_to_simplex(inside);
    CHECK(inside[0] == Approx(0.2));
    CHECK(inside[2] == Approx(0.5));
    // (2, 0) → (1, 0); (1, 1, 1) → thirds; (0.6, 0.6, −1) → (½, ½, 0).
    std::vector<double> a{2.0, 0.0}, b{1.0, 1.0, 1.0}, c{0.6, 0.6, -1.0};
    project_to_simplex(a);
    project_to_simplex(b);
    project_to_simplex(c);
    CHECK(a[0] == Approx(1.0));
    CHECK(a[1] == Approx(0.0).margin(1e-15));
    for (double x : b) CHECK(x == Approx(1.0 / 3.0));
    CHECK(c[0] == Approx(0.5));
    CHECK(c[1] == Approx(0.5));
    CHECK(c[2] == 0.0);
    // Of mean 1 over column means (0, 1, 2), the nearest to 0 is
    // (a, 1 − 2a, a) with 2a² + (1 − 2a)² least: a = 1/3.
    std::vector<double> d{0.0, 0.0, 0.0};
    project_to_simplex(d, MixtureMean{{0.0, 1.0, 2.0}, 1.0});
    for (double x : d) CHECK(x == Approx(1.0 / 3.0).epsilon(1e-9));
    // Already there: unchanged.
    std::vector<double> e{0.25, 0.5, 0.25};
    project_to_simplex(e, MixtureMean{{0.0, 1.0, 2.0}, 1.0});
    CHECK(e[0] == Approx(0.25).epsilon(1e-9));
    CHECK(e[1] == Approx(0.5).epsilon(1e-9));
}

TEST_CASE("projection onto the simplex: the KKT conditions on random vectors", "[core][simplex]") {
    // The projection p of v is the one point with p ≥ 0, Σ p = 1 and a τ
    // such that p_i = v_i − τ where p_i > 0 and v_i ≤ τ where p_i = 0.
    std::mt19937 rng(11);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const std::size_t n = 1 + std::size_t(trial) * 7 % 2000;
        const double spread = std::pow(10.0, trial % 7 - 4);  // from all kept to one kept
        std::vector<double> v(n);
        for (double& x : v) x = spread * normal(rng);
        std::vector<double> p = v;
        project_to_simplex(p);
        INFO("trial " << trial << ", n " << n << ", spread " << spread);
        double sum = 0.0, tau = 0.0;
        int kept = 0;
        for (std::size_t i = 0; i < n; ++i) {
            REQUIRE(p[i] >= 0.0);
            sum += p[i];
            if (p[i] > 0.0) tau += v[i] - p[i], ++kept;
        }
        REQUIRE(kept > 0);
        tau /= kept;
        CHECK(sum == Approx(1.0).epsilon(1e-12));
        for (std::size_t i = 0; i < n; ++i) {
            if (p[i] > 0.0) CHECK(v[i] - p[i] == Approx(tau).margin(1e-12 * (1.0 + std::abs(tau))));
            else CHECK(v[i] <= tau + 1e-12 * (1.0 + std::abs(tau)));
        }
    }
}

TEST_CASE("simplex least squares: closed-form minima, and a bound below every mixture", "[core][simplex]") {
    SECTION("a target between two components: half of each, 1/2 left over") {
        // K·p = (p1, p2) against (1, 1) on p1 + p2 = 1: minimum ½ at (½, ½).
        const SimplexFit fit = simplex_least_squares({{1.0, 0.0}, {0.0, 1.0}}, {1.0, 1.0}, {}, 1e-3);
        CHECK(fit.value == Approx(0.5).epsilon(1e-6));
        CHECK(fit.weights[0] == Approx(0.5).epsilon(1e-3));
        CHECK(fit.lower_bound <= 0.5 + 1e-12);
        CHECK(fit.lower_bound >= 0.5 * (1 - 1e-3));
    }
    SECTION("with a mean: the best mixture of that mean, not the best of all") {
        // Three one-bin histograms of means 0, 1, 2 against the first. At
        // mean 1, p = (a, 1 − 2a, a): f = (1 − a)² + (1 − 2a)² + a², least at
        // a = ½: f = ½ (without the mean, (1, 0, 0) and f = 0).
        const std::vector<std::vector<double>> k{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        const SimplexFit fit = simplex_least_squares(k, {1, 0, 0}, MixtureMean{{0, 1, 2}, 1.0}, 1e-4);
        CHECK(fit.value == Approx(0.5).epsilon(1e-3));
        CHECK(fit.lower_bound <= 0.5 + 1e-12);
        CHECK(fit.lower_bound >= 0.5 * (1 - 1e-4));
        CHECK(fit.weights[0] == Approx(0.5).epsilon(1e-2));
        CHECK(fit.weights[1] == Approx(0.0).margin(1e-2));
        CHECK(simplex_least_squares(k, {1, 0, 0}).value < 1e-6);
    }
    SECTION("a target that is a mixture is reached, its weights recovered") {
        // Four histograms of eight bins, linearly independent.
        const std::vector<std::vector<double>> k{{0.5, 0.5, 0, 0, 0, 0, 0, 0},
                                                 {0, 0.2, 0.6, 0.2, 0, 0, 0, 0},
                                                 {0, 0, 0, 0.3, 0.3, 0.4, 0, 0},
                                                 {0, 0, 0, 0, 0, 0.1, 0.45, 0.45}};
        const std::vector<double> truth{0.1, 0.4, 0.3, 0.2};
        std::vector<double> h(8, 0.0);
        for (std::size_t j = 0; j < 4; ++j)
            for (std::size_t i = 0; i < 8; ++i) h[i] += truth[j] * k[j][i];
        const SimplexFit fit = simplex_least_squares(k, h, {}, 1e-6, 1e-14, 200000);
        CHECK(fit.value < 1e-9);
        CHECK(fit.lower_bound <= fit.value);
        for (std::size_t j = 0; j < 4; ++j) CHECK(fit.weights[j] == Approx(truth[j]).margin(1e-3));
    }
    SECTION("the lower bound is below every one of 20 000 mixtures, and within 10^-3 of the fit") {
        // (asked for a gap of 10^-3 of the value)
        // Sixty shifted and widened bumps against a two-peaked target that
        // no mixture of them reaches exactly.
        std::vector<std::vector<double>> k;
        for (int j = 0; j < 60; ++j) {
            std::vector<double> col(64, 0.0);
            const double centre = j, width = 1.0 + 0.05 * j;
            double sum = 0.0;
            for (int i = 0; i < 64; ++i) sum += col[std::size_t(i)] = std::exp(-0.5 * (i - centre) * (i - centre) / (width * width));
            for (double& x : col) x /= sum;
            k.push_back(col);
        }
        std::vector<double> h(64, 0.0);
        h[10] = 0.7;
        h[40] = 0.3;
        const SimplexFit fit = simplex_least_squares(k, h, {}, 1e-3);
        REQUIRE(fit.lower_bound > 0.0);
        CHECK(fit.value - fit.lower_bound <= 1e-3 * fit.value + 1e-12);
        CHECK(std::accumulate(fit.weights.begin(), fit.weights.end(), 0.0) == Approx(1.0));
        std::mt19937 rng(7);
        std::uniform_int_distribution<int> pick(0, 59);
        const double least =
            least_of_random_mixtures(k, h, rng, [&](std::vector<double>& p, double w) { p[std::size_t(pick(rng))] += w; });
        INFO("bound " << fit.lower_bound << ", fit " << fit.value << ", best random " << least);
        CHECK(fit.lower_bound <= least);
        CHECK(fit.value <= least);
    }
    SECTION("with a mean over 400 columns: the bound is below every one of 20 000 mixtures of that mean") {
        // Histograms of a ramp of values scaled by a 1 % log grid (as the
        // least material distance builds them), their means rising with
        // the scale, against a two-peaked target whose mean is not asked.
        std::vector<std::vector<double>> k;
        MixtureMean mean;
        for (int j = 0; j < 400; ++j) {
            std::vector<double> col(64, 0.0);
            const double a = 0.05 * std::pow(1.01, j);
            for (int v = 1; v <= 100; ++v) col[std::size_t(std::min(63.0, std::floor(a * v * 0.25)))] += 0.01;
            double m = 0.0;
            for (int i = 0; i < 64; ++i) m += i * col[std::size_t(i)];
            k.push_back(col);
            mean.column_means.push_back(m);
        }
        mean.mean = 20.0;
        std::vector<double> h(64, 0.0);
        h[10] = 0.5;
        h[40] = 0.5;
        const SimplexFit fit = simplex_least_squares(k, h, mean, 1e-3);
        REQUIRE(fit.lower_bound > 0.0);
        CHECK(fit.value - fit.lower_bound <= 1e-3 * fit.value + 1e-12);
        double fitted_mean = 0.0;
        for (std::size_t j = 0; j < k.size(); ++j) fitted_mean += fit.weights[j] * mean.column_means[j];
        CHECK(fitted_mean == Approx(20.0).epsilon(1e-6));
        // Random mixtures of the mean: pairs of columns, one on either side
        // of it, each mixed to the mean, then mixed together.
        std::vector<std::size_t> under, over;
        for (std::size_t j = 0; j < k.size(); ++j)
            (mean.column_means[j] < mean.mean ? under : over).push_back(j);
        REQUIRE(!under.empty());
        REQUIRE(!over.empty());
        std::mt19937 rng(5);
        const double least = least_of_random_mixtures(k, h, rng, [&](std::vector<double>& p, double w) {
            const std::size_t i = under[std::size_t(rng() % under.size())];
            const std::size_t j = over[std::size_t(rng() % over.size())];
            const double di = mean.mean - mean.column_means[i], dj = mean.column_means[j] - mean.mean;
            p[i] += w * dj / (di + dj);
            p[j] += w * di / (di + dj);
        });
        INFO("bound " << fit.lower_bound << ", fit " << fit.value << ", best random " << least);
        CHECK(fit.lower_bound <= least);
        CHECK(fit.value <= least);
    }
}

TEST_CASE("simplex least squares near: a second distance held under a ceiling", "[simplex]") {
    // Three one-bin histograms at levels 0, 1 and 2, the mean held at 1:
    // p itself is the mixture's histogram. Fit h = (0, 1, 0) while staying
    // within √δ of g = (½, 0, ½): both lie on the simplex at mean 1, so the
    // nearest point of the ball to h is on the segment from g to h, √δ from
    // g, and min |p − h|² = (|h − g| − √δ)² = (√1.5 − √δ)².
    const std::vector<std::vector<double>> k = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::vector<double> h = {0, 1, 0};
    const MixtureMean mean{{0, 1, 2}, 1.0};
    for (double delta : {0.5, 0.1, 1.0}) {
        const double least = std::pow(std::sqrt(1.5) - std::sqrt(delta), 2.0);
        const NearSimplexFit fit = simplex_least_squares_near(k, h, MixtureNear{k, {0.5, 0, 0.5}, delta}, mean, 1e-3, 1e-9);
        INFO("delta " << delta << ": value " << fit.value << ", bound " << fit.lower_bound << ", least " << least
                      << ", " << fit.solves << " runs");
        REQUIRE(fit.feasible);
        CHECK(fit.lower_bound <= least + 1e-9);
        CHECK(fit.lower_bound >= least * (1.0 - 2e-3) - 1e-9);
        CHECK(fit.value >= least - 1e-9);
        CHECK(fit.value <= least * (1.0 + 2e-3) + 1e-9);
        CHECK(fit.second <= delta);
        CHECK(fit.weights[0] == Approx(fit.weights[2]).margin(1e-3));  // on the segment
    }
    // A ceiling the free fit is already under: one run, the free fit.
    const NearSimplexFit loose = simplex_least_squares_near(k, h, MixtureNear{k, {0.5, 0, 0.5}, 2.0}, mean, 1e-3, 1e-9);
    CHECK(loose.solves == 1);
    CHECK(loose.value < 1e-6);
}
