// The direction lobe's fit (core/direction_fit.h) against a field of
// directions made here: unit vectors normalize(a + J·x) over a cell, each
// turned by an offset uniform over an ellipse of known semi-axes on the
// tangent plane. The fit must give back the field's direction at any x
// and the ellipse (a uniform ellipse of semi-axis R has the variance R²/4
// along it); directions from two faces 60° apart, or no weight, give no
// lobe.

#include "jade/core/direction_fit.h"
#include "jade/core/random.h"
#include "jade/core/sampling.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

using namespace jade;

namespace {
constexpr double kDegrees = 180.0 / 3.14159265358979323846;

double angle_degrees(const glm::vec3& a, const glm::vec3& b) {
    return std::acos(std::clamp(double(glm::dot(glm::normalize(a), glm::normalize(b))), -1.0, 1.0)) * kDegrees;
}

// The field's direction at x (cell lengths from the centre).
glm::vec3 field(const glm::vec3& x) {
    const glm::vec3 a = glm::normalize(glm::vec3(0.2f, -0.3f, 0.93f));
    // About 6° of turn across the cell along x, 3° along z.
    const glm::vec3 turn = 0.1f * x.x * glm::vec3(1.f, 0.f, 0.f) + 0.05f * x.z * glm::vec3(0.f, 1.f, 0.f);
    return glm::normalize(a + turn);
}
}  // namespace

TEST_CASE("a direction lobe gives back an affine field of directions and the ellipse they spread over",
          "[direction_fit]") {
    const float r_major = 0.08f, r_minor = 0.03f;
    DirectionSums sums;
    SampleStream rng(21, 0, 0);
    for (int k = 0; k < 200000; ++k) {
        const glm::vec3 x(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f);
        const glm::vec3 a = field(x);
        glm::vec3 t, b;
        orthonormal_basis(a, t, b);
        // The ellipse's major axis along the tangent nearest world x.
        const glm::vec3 major = glm::normalize(glm::vec3(1.f, 0.f, 0.f) - a.x * a);
        const glm::vec3 minor = glm::cross(a, major);
        const float rho = std::sqrt(rng.uniform()), phi = 6.2831853f * rng.uniform();
        const glm::vec3 w =
            glm::normalize(a + r_major * rho * std::cos(phi) * major + r_minor * rho * std::sin(phi) * minor);
        StretchSums stretch;
        stretch.add(0.5 + rng.uniform(), glm::dvec3(x));
        sums.add(stretch, w);
    }
    DirectionFitSettings exact;
    exact.margin = 1.0;
    exact.ridge = 0.0;
    const std::optional<DirectionLobe> lobe = fit_direction_lobe(sums, exact);
    REQUIRE(lobe);
    for (const glm::vec3& x : {glm::vec3(0.f), glm::vec3(0.45f, -0.2f, 0.3f), glm::vec3(-0.4f, 0.4f, -0.45f)}) {
        const std::optional<EllipticCone> cone = lobe->cone(x);
        REQUIRE(cone);
        INFO("x = (" << x.x << ", " << x.y << ", " << x.z << ")");
        // A tenth of a degree: the ellipse's offsets average out, and the
        // normalisation bends the field from affine by (turn)²/2.
        CHECK(angle_degrees(cone->axis, field(x)) < 0.1);
        // The major axis: world x on the plane tangent at the axis.
        const glm::vec3 x_tangent = glm::normalize(glm::vec3(1.f, 0.f, 0.f) - cone->axis.x * cone->axis);
        CHECK(std::abs(glm::dot(cone->major, x_tangent)) > 0.999f);
    }
    CHECK(lobe->r_major == Approx(r_major).epsilon(0.03));
    CHECK(lobe->r_minor == Approx(r_minor).epsilon(0.03));
    // The margin widens both radii by its factor.
    DirectionFitSettings wider = exact;
    wider.margin = DirectionFitSettings{}.margin;
    const std::optional<DirectionLobe> wide = fit_direction_lobe(sums, wider);
    REQUIRE(wide);
    CHECK(wide->r_major == Approx(wider.margin * lobe->r_major).epsilon(1e-5));
}

TEST_CASE("directions from two faces 60° apart, or no light at all, make no lobe", "[direction_fit]") {
    DirectionSums sums;
    CHECK_FALSE(fit_direction_lobe(sums));
    SampleStream rng(22, 0, 0);
    const glm::vec3 faces[2] = {glm::vec3(0.5f, 0.f, 0.866f), glm::vec3(-0.5f, 0.f, 0.866f)};
    for (int k = 0; k < 20000; ++k) {
        StretchSums stretch;
        stretch.add(1.0, glm::dvec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
        sums.add(stretch, faces[k % 2]);
    }
    // Their spread about the mean, 2σ = 2 sin 30° = 1 on the tangent plane,
    // is wider than any lobe may be.
    CHECK(2.0 * 0.5 > DirectionFitSettings{}.widest);
    CHECK_FALSE(fit_direction_lobe(sums));
}
