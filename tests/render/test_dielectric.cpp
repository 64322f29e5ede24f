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

TEST_CASE("strict normals: a shading normal that sends a grazing ray through its triangle is caught", "[dielectric]") {
    // The triangle z = 0 (geometric normal +z, outward); a ray inside the
    // object (z < 0) arrives at 80° from the normal.
    const glm::vec3 ng(0, 0, 1);
    const double theta = 80.0 * kPi / 180.0;
    const glm::vec3 d(float(std::sin(theta)), 0.f, float(std::cos(theta)));  // going up, toward +x
    // About the triangle's own normal the reflection stays inside.
    CHECK(on_sampled_side(d, reflect(d, ng), ng, true));
    // A shading normal tilted 8° away from the ray (an interpolated normal
    // on a coarse curved mesh) still faces the ray's side (88° from it), so
    // the interface bends by it; the ray's mirror about it lies at
    // 180° + 2·(−8°) − 80° = 84° from the triangle's normal: 6° above the
    // triangle, outside the object.
    const auto tilted = [&](double degrees) {
        const double b = degrees * kPi / 180.0;
        return glm::vec3(float(std::sin(b)), 0.f, float(std::cos(b)));
    };
    REQUIRE(glm::dot(d, tilted(-8.0)) > 0.f);
    const glm::vec3 leak = reflect(d, tilted(-8.0));
    CHECK(leak.z == Approx(std::cos(84.0 * kPi / 180.0)).margin(1e-5));
    CHECK_FALSE(on_sampled_side(d, leak, ng, true));
    // Tilted 15° toward it, the mirror lies at 130°: inside.
    CHECK(reflect(d, tilted(15.0)).z == Approx(std::cos(130.0 * kPi / 180.0)).margin(1e-5));
    CHECK(on_sampled_side(d, reflect(d, tilted(15.0)), ng, true));
    // A refraction out must leave; one bent back below the triangle does not.
    const glm::vec3 steep(0.2f, 0.f, 0.979796f);
    glm::vec3 out;
    REQUIRE(refract(steep, -ng, 1.f / 1.6f, out));
    CHECK(on_sampled_side(steep, out, ng, false));
    CHECK_FALSE(on_sampled_side(steep, glm::vec3(out.x, out.y, -out.z), ng, false));
    // From outside: a reflection goes back up, a refraction goes in.
    const glm::vec3 down = incoming(0.5);
    CHECK(on_sampled_side(down, reflect(down, ng), ng, true));
    CHECK_FALSE(on_sampled_side(down, reflect(down, ng), ng, false));
    REQUIRE(refract(down, ng, 1.6f, out));
    CHECK(on_sampled_side(down, out, ng, false));
    // Along the triangle is neither side.
    CHECK_FALSE(on_sampled_side(d, glm::vec3(1, 0, 0), ng, true));
    CHECK_FALSE(on_sampled_side(d, glm::vec3(1, 0, 0), ng, false));
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
