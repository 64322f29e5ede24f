// Chandrasekhar's H-function against what is known of it independently of
// the integral form the library evaluates: its zeroth moment in closed form,
// its tabulated value at a = 1, the integral equation it solves, and the
// half-space albedo's limits for weak and for nearly conservative scattering.

#include "jade/core/chandrasekhar.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using jade::ChandrasekharH;

TEST_CASE("H-function: the zeroth moment is (2/a)(1 - sqrt(1 - a)) for every albedo", "[chandrasekhar]") {
    for (double a : {1e-3, 0.3, 0.5, 0.9, 0.99, 1 - 1e-6, 1.0}) {
        INFO("a = " << a);
        CHECK(ChandrasekharH(a).moment(0) == Approx(2 / a * (1 - std::sqrt(1 - a))).epsilon(1e-6));
    }
}

TEST_CASE("H-function: conservative scattering has H(1) = 2.9078 and first moment 2/sqrt(3)", "[chandrasekhar]") {
    const ChandrasekharH H(1.0);
    CHECK(H(1.0) == Approx(2.9078).margin(1e-4));  // Chandrasekhar 1960, Table V
    CHECK(H(0.0) == Approx(1.0).margin(1e-12));
    CHECK(H.moment(1) == Approx(2 / std::sqrt(3.0)).epsilon(1e-5));
    CHECK(H.diffuse_albedo() == Approx(1.0).margin(1e-12));
}

TEST_CASE("H-function: it solves its integral equation", "[chandrasekhar]") {
    // 1/H(μ) = √(1 − a) + (a/2) ∫₀¹ μ' H(μ') / (μ + μ') dμ', the integral by
    // the trapezoid rule on a fine grid (H is smooth on [0, 1]).
    for (double a : {0.5, 0.9, 0.999}) {
        const ChandrasekharH H(a);
        const int n = 4000;
        std::vector<double> h(n + 1);
        for (int i = 0; i <= n; ++i) h[i] = H(double(i) / n);
        for (double mu : {0.1, 0.5, 1.0}) {
            double s = 0;
            for (int i = 0; i <= n; ++i) {
                const double m = double(i) / n;
                s += (i == 0 || i == n ? 0.5 : 1.0) * m * h[i] / (mu + m);
            }
            s /= n;
            INFO("a = " << a << ", mu = " << mu);
            CHECK(1 / H(mu) == Approx(std::sqrt(1 - a) + 0.5 * a * s).epsilon(1e-6));
        }
    }
}

TEST_CASE("half-space albedo: single scattering when weak and diffusion when nearly conservative",
          "[chandrasekhar]") {
    // Weak: to first order in a, H = 1 + (a/2) μ ln(1 + 1/μ), so the diffuse
    // albedo is a (1/2 − ∫₀¹ μ² ln(1 + 1/μ) dμ) = a (2/3 − (2/3) ln 2).
    const double a = 1e-4;
    CHECK(ChandrasekharH(a).diffuse_albedo() / a == Approx(2.0 / 3.0 - 2.0 / 3.0 * std::log(2.0)).epsilon(1e-3));
    // Nearly conservative: 1 − A → 2 α₁ √(1 − a) = (4/√3) √(1 − a).
    const double b = 1 - 1e-8;
    CHECK((1 - ChandrasekharH(b).diffuse_albedo()) / (4 / std::sqrt(3.0) * std::sqrt(1 - b)) ==
          Approx(1.0).epsilon(1e-3));
}
