// Phase functions against their analytic distributions: normalisation, and
// χ² goodness of fit of the sampler to Henyey–Greenstein's closed-form CDF.

#include "jade/render/phase_function.h"
#include "jade/core/sampling.h"
#include "jade/core/random.h"

#include "support/chi2.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>

using namespace jade;

namespace {
constexpr double kPi = 3.14159265358979323846;

// P(cos θ ≤ mu) for HG: (1 − g²)/(2g) · ((1 + g² − 2g mu)^{-1/2} − 1/(1 + g)); (mu + 1)/2 at g = 0.
double hg_cdf(double mu, double g) {
    if (g == 0.0) return 0.5 * (mu + 1.0);
    return (1.0 - g * g) / (2.0 * g) * (1.0 / std::sqrt(1.0 + g * g - 2.0 * g * mu) - 1.0 / (1.0 + g));
}
}  // namespace

TEST_CASE("the phase function integrates to 1 over the sphere", "[phase]") {
    for (float g : {0.f, 0.3f, -0.5f, 0.9f}) {
        const PhaseFunction phase(g);
        const glm::vec3 in = glm::normalize(glm::vec3(0.3f, -0.2f, 0.9f));
        // Midpoint rule in (cos θ, φ) about `in`: the integrand is smooth.
        glm::vec3 t, b;
        orthonormal_basis(in, t, b);
        const int nu = 4000, nphi = 16;
        double sum = 0;
        for (int i = 0; i < nu; ++i) {
            const double mu = -1.0 + (i + 0.5) * 2.0 / nu;
            const double s = std::sqrt(1 - mu * mu);
            for (int j = 0; j < nphi; ++j) {
                const double phi = (j + 0.5) * 2 * kPi / nphi;
                const glm::vec3 out = glm::vec3(float(s * std::cos(phi))) * t +
                                      glm::vec3(float(s * std::sin(phi))) * b + float(mu) * in;
                sum += phase.eval(in, out);
            }
        }
        CHECK(sum * (2.0 / nu) * (2 * kPi / nphi) == Approx(1.0).epsilon(2e-3));
    }
}

TEST_CASE("phase sampling follows Henyey-Greenstein (chi-square)", "[phase]") {
    for (float g : {0.f, 0.5f, -0.3f, 0.85f}) {
        const PhaseFunction phase(g);
        const glm::vec3 in = glm::normalize(glm::vec3(-0.4f, 0.7f, 0.2f));
        glm::vec3 t, b;
        orthonormal_basis(in, t, b);
        const int n_mu = 20, n_phi = 8, samples = 200000;
        std::vector<double> observed(n_mu * n_phi, 0.0), expected(n_mu * n_phi, 0.0);
        SampleStream rng(7, std::uint64_t(g * 1000 + 5000), 0);
        for (int i = 0; i < samples; ++i) {
            const glm::vec3 out = phase.sample(in, rng.uniform(), rng.uniform());
            REQUIRE(std::abs(glm::length(out) - 1.f) < 1e-4f);
            const double mu = std::clamp(double(glm::dot(in, out)), -1.0, 1.0);
            double phi = std::atan2(double(glm::dot(out, b)), double(glm::dot(out, t)));
            if (phi < 0) phi += 2 * kPi;
            // Bins equal in cos θ for the isotropic case; fine enough for all g.
            const int bm = std::min(n_mu - 1, int((mu + 1.0) * 0.5 * n_mu));
            const int bp = std::min(n_phi - 1, int(phi / (2 * kPi) * n_phi));
            observed[bm * n_phi + bp] += 1;
        }
        for (int bm = 0; bm < n_mu; ++bm) {
            const double lo = -1.0 + 2.0 * bm / n_mu, hi = -1.0 + 2.0 * (bm + 1) / n_mu;
            const double p = hg_cdf(hi, g) - hg_cdf(lo, g);
            for (int bp = 0; bp < n_phi; ++bp) expected[bm * n_phi + bp] = samples * p / n_phi;
        }
        int dof = 0;
        const double stat = jade_test::chi2_statistic(observed, expected, dof);
        INFO("g = " << g << ", chi2 = " << stat << " with " << dof << " dof");
        CHECK(stat < jade_test::chi2_critical_1e4(dof));
        // The sampler must also be able to fail: the same counts against the
        // isotropic law are rejected whenever g is not small.
        if (std::abs(g) > 0.2f) {
            std::vector<double> iso(expected.size(), double(samples) / expected.size());
            int dof_iso = 0;
            const double stat_iso = jade_test::chi2_statistic(observed, iso, dof_iso);
            CHECK(stat_iso > jade_test::chi2_critical_1e4(dof_iso));
        }
    }
}

TEST_CASE("HG's mean cosine is g", "[phase]") {
    const PhaseFunction phase(0.6f);
    const glm::vec3 in(0, 0, 1);
    SampleStream rng(3, 0, 0);
    double sum = 0;
    const int n = 400000;
    for (int i = 0; i < n; ++i) sum += phase.sample(in, rng.uniform(), rng.uniform()).z;
    // Var[cos θ] <= 1, so 5 standard errors are below 5 / sqrt(n) = 0.008.
    CHECK(std::abs(sum / n - 0.6) < 5.0 / std::sqrt(double(n)));
}

TEST_CASE("asymmetry outside (-1, 1) is refused", "[phase]") {
    CHECK_THROWS(PhaseFunction(1.f));
    CHECK_THROWS(PhaseFunction(-1.5f));
}

TEST_CASE("Henyey-Greenstein stays finite and exact as |g| approaches 1", "[phase]") {
    // The lobe of g = 0.9999 is about 1e-4 rad wide, below what a float dot
    // product resolves (1 − cos θ ≈ 5e-9): angles are measured here as
    // atan2(|in × out|, in · out) in double, and the sampler's quartiles
    // compared with HG's closed-form CDF (in double), within 4.5 binomial σ.
    for (float g : {0.9999f, -0.9999f, 0.999999f, -0.999999f}) {
        INFO("g = " << g);
        const PhaseFunction phase(g);
        const glm::vec3 in = glm::normalize(glm::vec3(0.2f, -0.5f, 0.8f));
        const glm::dvec3 in_d(in);
        auto cos_theta = [&](const glm::vec3& out) {
            const glm::dvec3 o(out);
            return std::cos(std::atan2(glm::length(glm::cross(in_d, o)), glm::dot(in_d, o)));
        };
        // The quartiles of cos θ, by bisection on the CDF.
        double quartile[3];
        for (int q = 0; q < 3; ++q) {
            double lo = -1, hi = 1;
            for (int it = 0; it < 200; ++it) {
                const double mid = 0.5 * (lo + hi);
                (hg_cdf(mid, g) < 0.25 * (q + 1) ? lo : hi) = mid;
            }
            quartile[q] = 0.5 * (lo + hi);
        }
        SampleStream rng(11, 12, 13);
        const int n = 100000;
        int below[3] = {0, 0, 0};
        for (int i = 0; i < n; ++i) {
            const float u1 = rng.uniform(), u2 = rng.uniform();
            const glm::vec3 out = phase.sample(in, u1, u2);
            const float f = phase.eval(in, out);
            REQUIRE(std::isfinite(f));
            REQUIRE(f > 0.f);
            const double c = cos_theta(out);
            for (int q = 0; q < 3; ++q) below[q] += c <= quartile[q];
        }
        for (int q = 0; q < 3; ++q) {
            const double p = 0.25 * (q + 1);
            CHECK(std::abs(below[q] - n * p) < 4.5 * std::sqrt(n * p * (1 - p)));
        }
        // At the lobe's peak the density is (1 + |g|) / (4π (1 − |g|)²): finite, and exact.
        const glm::vec3 peak = g > 0 ? in : -in;
        CHECK(phase.eval(in, peak) == Approx((1 + std::abs(g)) / (4 * kPi * (1 - std::abs(g)) * (1 - std::abs(g)))).epsilon(1e-3));
    }
}
