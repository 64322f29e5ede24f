// The analytic sphere against closed-form answers (distances along known
// rays, the exact distance to the surface, the normal's derivative by finite
// differences) and against a finely tessellated sphere traced by Embree.

#include "jade/geometry/mesh_accel.h"
#include "jade/geometry/sphere_boundary.h"
#include "jade/core/error.h"
#include "jade/core/random.h"
#include "jade/core/sampling.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

using namespace jade;

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}

TEST_CASE("the analytic sphere: hits along known rays", "[geometry][sphere]") {
    const SphereBoundary s({1.f, 2.f, 3.f}, 0.5f);
    const glm::vec3 c(1.f, 2.f, 3.f);
    // From outside, straight at the centre: the near side at distance 4.5.
    auto hit = s.intersect(c + glm::vec3(0, 0, 5), {0, 0, -1}, 0.f, kInf);
    REQUIRE(hit);
    CHECK(hit->t == Approx(4.5f).epsilon(1e-6));
    CHECK(glm::length(hit->geometric_normal - glm::vec3(0, 0, 1)) < 1e-6f);
    CHECK(hit->shading_normal == hit->geometric_normal);
    // The far side, beyond the near one.
    hit = s.intersect(c + glm::vec3(0, 0, 5), {0, 0, -1}, 4.6f, kInf);
    REQUIRE(hit);
    CHECK(hit->t == Approx(5.5f).epsilon(1e-6));
    CHECK(glm::length(hit->geometric_normal - glm::vec3(0, 0, -1)) < 1e-6f);
    // Within tmax only, and a miss beside it.
    CHECK(!s.intersect(c + glm::vec3(0, 0, 5), {0, 0, -1}, 0.f, 4.4f));
    CHECK(!s.intersect(c + glm::vec3(0.51f, 0, 5), {0, 0, -1}, 0.f, kInf));
    // From inside, one hit ahead at r − offset; the outward normal.
    hit = s.intersect(c + glm::vec3(0.1f, 0, 0), {1, 0, 0}, 0.f, kInf);
    REQUIRE(hit);
    CHECK(hit->t == Approx(0.4f).epsilon(1e-6));
    CHECK(glm::length(hit->geometric_normal - glm::vec3(1, 0, 0)) < 1e-6f);
    // A ray leaving the surface outward meets nothing more; inward, the far side.
    const glm::vec3 on = c + glm::vec3(0, 0.5f, 0);
    CHECK(!s.intersect(on, {0, 1, 0}, 1e-6f, kInf));
    hit = s.intersect(on, {0, -1, 0}, 1e-6f, kInf);
    REQUIRE(hit);
    CHECK(hit->t == Approx(1.f).epsilon(1e-6));
    // occluded() and intersect_primitive() say what intersect() says.
    CHECK(s.occluded(c + glm::vec3(0, 0, 5), {0, 0, -1}, 0.f, 4.6f));
    CHECK(!s.occluded(c + glm::vec3(0, 0, 5), {0, 0, -1}, 0.f, 4.4f));
    hit = s.intersect_primitive(c + glm::vec3(0.1f, 0, 0), {1, 0, 0}, 0);
    REQUIRE(hit);
    CHECK(hit->t == Approx(0.4f).epsilon(1e-6));
    // Bounds, hull, convexity, distance.
    CHECK(s.bounds().min == c - glm::vec3(0.5f));
    CHECK(s.bounds().max == c + glm::vec3(0.5f));
    CHECK(s.hull_points().size() == 8);
    CHECK(s.convex());
    CHECK(s.distance_to_surface(c + glm::vec3(0.2f, 0, 0), 1.f) == Approx(0.3f).epsilon(1e-6));
    CHECK(s.distance_to_surface(c + glm::vec3(0, 2.f, 0), 1.f) == Approx(1.f));
    CHECK(s.distance_to_surface(c + glm::vec3(0, 1.f, 0), 10.f) == Approx(0.5f).epsilon(1e-6));
    CHECK(s.clearance(c) == 0.f);  // no bound: a flight asks at once
    CHECK_THROWS_AS(SphereBoundary(c, 0.f), Error);
    CHECK_THROWS_AS(SphereBoundary(c, -1.f), Error);
    CHECK_THROWS_AS(SphereBoundary({kInf, 0, 0}, 1.f), Error);
}

TEST_CASE("the analytic sphere's normal is exact in every octant", "[geometry][sphere]") {
    // The hit stores its normal in two numbers (octahedral coordinates); read
    // back it must be the exact normal, poles and the z < 0 half included.
    const SphereBoundary s({0.f, 0.f, 0.f}, 2.f);
    SplitMix64 rng(7);
    float worst = 0.f;
    for (int i = 0; i < 20000; ++i) {
        const glm::vec3 n = i < 6 ? glm::vec3(i % 3 == 0, i % 3 == 1, i % 3 == 2) * (i < 3 ? 1.f : -1.f)
                                  : uniform_sphere(float(rng.uniform()), float(rng.uniform()));
        // A ray from outside straight at the point 2n.
        const auto hit = s.intersect(4.f * n, -n, 0.f, kInf);
        REQUIRE(hit);
        worst = std::max(worst, glm::length(hit->geometric_normal - n));
        CHECK(hit->t == Approx(2.f).epsilon(1e-5));
    }
    CHECK(worst < 2e-6f);
}

TEST_CASE("the analytic sphere agrees with a fine tessellation traced by Embree", "[geometry][sphere]") {
    const SphereBoundary s({0.f, 0.f, 0.f}, 1.f);
    const TriangleMesh mesh = icosphere(6, 1.f);  // faces within 2e-4 of the sphere
    const MeshAccel accel(mesh);
    SplitMix64 rng(11);
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
        // Rays from inside and from outside, in random directions.
        const float r = i % 2 ? 0.9f * float(rng.uniform()) : 1.5f + float(rng.uniform());
        const glm::vec3 o = r * uniform_sphere(float(rng.uniform()), float(rng.uniform()));
        const glm::vec3 d = uniform_sphere(float(rng.uniform()), float(rng.uniform()));
        const auto a = s.intersect(o, d, 0.f, kInf);
        const auto m = accel.intersect(o, d, 0.f, kInf);
        // A ray grazing the sphere may miss the inscribed mesh, never the
        // other way round.
        if (!a) CHECK(!m);
        if (a && !m) CHECK(glm::length(o + glm::dot(-o, d) * d) > 0.99f);
        if (!a || !m) continue;
        ++hits;
        CHECK(std::abs(a->t - m->t) < 2e-3f);
        CHECK(glm::length(a->shading_normal - m->shading_normal) < 2e-3f);
    }
    CHECK(hits > 2000);  // every ray from inside, and some from outside
    // The packet of one origin reports what the single queries do.
    glm::vec3 dirs[Boundary::kPacket];
    for (auto& d : dirs) d = glm::normalize(glm::vec3(0.3f * float(rng.uniform()) - 0.15f, 0.2f, -1.f));
    std::optional<SurfaceHit> packet[Boundary::kPacket];
    s.intersect_packet({0.f, 0.f, 3.f}, dirs, Boundary::kPacket, packet);
    for (int i = 0; i < Boundary::kPacket; ++i) {
        const auto one = s.intersect({0.f, 0.f, 3.f}, dirs[i], 0.f, kInf);
        REQUIRE(one.has_value() == packet[i].has_value());
        if (one) CHECK(one->t == packet[i]->t);
    }
}

TEST_CASE("the analytic sphere's normal turns as its differential says", "[geometry][sphere]") {
    const glm::vec3 c(0.2f, -0.1f, 0.3f);
    const float r = 0.7f;
    const SphereBoundary s(c, r);
    SplitMix64 rng(3);
    for (int i = 0; i < 200; ++i) {
        const glm::vec3 n = uniform_sphere(float(rng.uniform()), float(rng.uniform()));
        const auto hit = s.intersect(c + 2.f * n, -n, 0.f, kInf);
        REQUIRE(hit);
        const SurfaceDifferential sd = s.differential(*hit);
        CHECK(std::abs(glm::dot(sd.tangent[0], sd.tangent[1])) < 1e-5f);
        for (int k = 0; k < 2; ++k) {
            CHECK(glm::length(sd.tangent[k]) == Approx(1.f).epsilon(1e-5));
            CHECK(std::abs(glm::dot(sd.tangent[k], hit->shading_normal)) < 1e-5f);
            // The normal at the surface point a small step along the tangent,
            // against the derivative times the step.
            const float h = 1e-3f;
            const glm::vec3 p = c + r * hit->shading_normal + h * sd.tangent[k];
            const glm::vec3 moved = glm::normalize(p - c);
            const glm::vec3 fd = (moved - hit->shading_normal) / h;
            CHECK(glm::length(fd - sd.dn[k]) < 5e-3f);
        }
    }
}

TEST_CASE("the analytic sphere's bounded queries: a segment meets the surface exactly when the ray does within it",
          "[geometry][sphere]") {
    // Free flights ask with a finite tmax, and segments that end inside are
    // answered by a float test: it must never miss a crossing, also for
    // segments ending just past the surface.
    const glm::vec3 c(0.3f, -0.2f, 0.1f);
    const SphereBoundary s(c, 1.5f);
    SplitMix64 rng(19);
    int crossing = 0, inside = 0;
    for (int i = 0; i < 100000; ++i) {
        const glm::vec3 o = c + 1.5f * std::cbrt(float(rng.uniform())) *
                                    uniform_sphere(float(rng.uniform()), float(rng.uniform()));
        const glm::vec3 d = uniform_sphere(float(rng.uniform()), float(rng.uniform()));
        const auto ray = s.intersect(o, d, 0.f, kInf);
        REQUIRE(ray);
        // Segments ending near the exit: within 1e-3 of it on either side, or anywhere.
        const float tmax = i % 2 ? ray->t * (1.f + 1e-3f * (2.f * float(rng.uniform()) - 1.f))
                                 : 3.f * float(rng.uniform());
        // (At tmax equal to the hit's float distance the double root decides.)
        if (std::abs(tmax - ray->t) <= 1e-6f * ray->t) continue;
        const auto seg = s.intersect(o, d, 0.f, tmax);
        CHECK(seg.has_value() == (ray->t < tmax));
        if (seg) CHECK(seg->t == ray->t);
        (ray->t < tmax ? crossing : inside) += 1;
        CHECK(s.occluded(o, d, 0.f, tmax) == (ray->t < tmax));
    }
    CHECK(crossing > 30000);
    CHECK(inside > 30000);
}
