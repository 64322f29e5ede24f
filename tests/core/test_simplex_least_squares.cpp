// Least squares over the probability simplex against closed-form minima, and
// its lower bound against every mixture tried.
#include "jade/core/simplex_least_squares.h"

#include <catch2/catch.hpp>

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
        std::exponential_distribution<double> e(1.0);
        std::uniform_int_distribution<int> pick(0, 59);
        double least = 1e9;
        for (int t = 0; t < 20000; ++t) {
            // Sparse random mixtures (one to four components) reach near the
            // optimum more often than dense ones.
            std::vector<double> p(60, 0.0);
            const int parts = 1 + t % 4;
            double sum = 0.0;
            for (int s = 0; s < parts; ++s) {
                const double w = e(rng);
                p[std::size_t(pick(rng))] += w;
                sum += w;
            }
            for (double& x : p) x /= sum;
            least = std::min(least, objective(k, h, p));
        }
        INFO("bound " << fit.lower_bound << ", fit " << fit.value << ", best random " << least);
        CHECK(fit.lower_bound <= least);
        CHECK(fit.value <= least);
    }
}
