// The smooth dielectric boundary against optics: Fresnel's equations at known
// angles, Snell's law, total internal reflection, and the frequencies with
// which each mode picks reflection (binomial z-tests, χ² over angles).

#include "jade/render/dielectric.h"
#include "jade/core/random.h"

#include "support/chi2.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>

using namespace jade;

namespace {
constexpr double kPi = 3.14159265358979323846;
glm::vec3 incoming(double theta) {  // toward the surface z = 0 from above, normal +z
    return glm::vec3(float(std::sin(theta)), 0.f, float(-std::cos(theta)));
}
}  // namespace

TEST_CASE("Fresnel reflectance at normal incidence, Brewster's angle and grazing", "[dielectric]") {
    const float n = 1.6f;
    CHECK(fresnel_dielectric(1.f, n) == Approx(std::pow((1.6 - 1) / (1.6 + 1), 2)).epsilon(1e-5));
    // At Brewster's angle the parallel polarisation is not reflected: R = R_perp / 2.
    const double tb = std::atan(1.6), tt = std::asin(std::sin(tb) / 1.6);
    const double rs = std::pow((std::cos(tb) - 1.6 * std::cos(tt)) / (std::cos(tb) + 1.6 * std::cos(tt)), 2);
    CHECK(fresnel_dielectric(float(std::cos(tb)), n) == Approx(0.5 * rs).epsilon(1e-4));
    CHECK(fresnel_dielectric(1e-4f, n) == Approx(1.0).margin(1e-3));
    // From inside, beyond the critical angle asin(1/1.6) = 38.68°, everything reflects.
    CHECK(fresnel_dielectric(float(std::cos(0.70)), 1.f / n) == 1.f);
    CHECK(fresnel_dielectric(float(std::cos(0.65)), 1.f / n) < 1.f);
}

TEST_CASE("refraction obeys Snell's law and reflection mirrors", "[dielectric]") {
    const glm::vec3 nrm(0, 0, 1);
    for (double theta : {0.0, 0.3, 0.8, 1.3}) {
        const glm::vec3 d = incoming(theta);
        glm::vec3 t;
        REQUIRE(refract(d, nrm, 1.6f, t));
        CHECK(std::sqrt(t.x * t.x + t.y * t.y) == Approx(std::sin(theta) / 1.6).margin(1e-5));
        CHECK(t.z < 0.f);
        const glm::vec3 r = reflect(d, nrm);
        CHECK(r.x == Approx(d.x).margin(1e-6));
        CHECK(r.z == Approx(-d.z).margin(1e-6));
    }
    glm::vec3 t;
    CHECK_FALSE(refract(incoming(0.8), nrm, 1.f / 1.6f, t));  // total internal reflection
}

TEST_CASE("each mode reflects with its probability (chi-square over angles)", "[dielectric]") {
    const int per_angle = 40000;
    std::vector<double> angles;
    for (int i = 0; i < 12; ++i) angles.push_back((i + 0.5) / 12.0 * 0.5 * kPi * 0.98);
    for (BoundaryMode mode : {BoundaryMode::Fresnel, BoundaryMode::Split}) {
        for (bool entering : {true, false}) {
            BoundaryParams p;
            p.mode = mode;
            std::vector<double> observed, expected;
            int free_angles = 0;  // angles where both branches can happen: one dof each
            SampleStream rng(11, std::uint64_t(mode == BoundaryMode::Split) * 2 + entering, 0);
            for (double theta : angles) {
                // From outside the ray travels down (−z) onto the surface z = 0
                // with normal +z; from inside it travels up toward it.
                const glm::vec3 dd = entering ? incoming(theta)
                                              : glm::vec3(float(std::sin(theta)), 0.f, float(std::cos(theta)));
                const float eta = entering ? 1.6f : 1.f / 1.6f;
                // Expected reflection probability, from Snell + Fresnel written out here.
                const double sin_t = std::sin(theta) / eta;
                double pr;
                if (sin_t >= 1.0) pr = 1.0;
                else if (mode == BoundaryMode::Split) pr = 0.5;
                else {
                    const double ci = std::cos(theta), ct = std::sqrt(1 - sin_t * sin_t);
                    const double rp = (eta * ci - ct) / (eta * ci + ct), rs = (ci - eta * ct) / (ci + eta * ct);
                    pr = 0.5 * (rp * rp + rs * rs);
                }
                if (pr > 0.0 && pr < 1.0) ++free_angles;
                int reflected = 0;
                for (int i = 0; i < per_angle; ++i) {
                    const BoundarySample s = sample_boundary(p, dd, glm::vec3(0, 0, 1), entering, rng.uniform());
                    // The direction must lie on the side its branch says.
                    REQUIRE((s.direction.z * dd.z > 0) == !s.reflected);
                    reflected += s.reflected;
                }
                observed.push_back(reflected);
                observed.push_back(per_angle - reflected);
                expected.push_back(per_angle * pr);
                expected.push_back(per_angle * (1 - pr));
            }
            int pooled_dof = 0;
            const double stat = jade_test::chi2_statistic(observed, expected, pooled_dof);
            INFO(to_string(mode) << (entering ? " entering" : " leaving") << ": chi2 " << stat
                                 << " over " << free_angles << " angles");
            REQUIRE(free_angles >= 5);
            CHECK(stat < jade_test::chi2_critical_1e4(free_angles));
        }
    }
}
