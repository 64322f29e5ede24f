// Embree ray queries against analytic geometry: distances, normals, and no
// ray escaping a closed surface through its edges.

#include "jade/geometry/mesh_accel.h"
#include "jade/core/random.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <optional>

using namespace jade;

namespace {

TriangleMesh unit_box() {  // [-1, 1]^3, outward winding
    TriangleMesh m;
    m.positions = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                   {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    const std::uint32_t quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                       {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    m.normals.assign(m.positions.size(), glm::vec3(0, 0, 1));
    return m;
}

// Distance from p (inside the box) along unit d to the box's surface.
float exit_distance(glm::vec3 p, glm::vec3 d) {
    float t = 1e30f;
    for (int k = 0; k < 3; ++k)
        if (d[k] != 0.f) t = std::min(t, ((d[k] > 0 ? 1.f : -1.f) - p[k]) / d[k]);
    return t;
}

}  // namespace

TEST_CASE("rays hit the box at the analytic distance with outward normals", "[mesh_accel]") {
    const TriangleMesh box = unit_box();
    const MeshAccel accel(box, true);
    auto hit = accel.intersect({0.2f, -0.3f, 5.f}, {0, 0, -1}, 0.f, 1e30f);
    REQUIRE(hit);
    CHECK(hit->t == Approx(4.f));
    CHECK(hit->geometric_normal == glm::vec3(0, 0, 1));
    CHECK(hit->shading_normal == glm::vec3(0, 0, 1));  // flat: face normal

    hit = accel.intersect({0, 0, 0}, {1, 0, 0}, 0.f, 1e30f);
    REQUIRE(hit);
    CHECK(hit->t == Approx(1.f));
    CHECK(hit->geometric_normal == glm::vec3(1, 0, 0));  // outward, seen from inside too

    CHECK_FALSE(accel.intersect({5, 5, 5}, {0, 0, 1}, 0.f, 1e30f));
    CHECK_FALSE(accel.intersect({0, 0, 5}, {0, 0, -1}, 0.f, 3.f));  // beyond tmax
}

TEST_CASE("the occlusion query agrees with the analytic box and with the closest hit", "[mesh_accel]") {
    const TriangleMesh box = unit_box();
    const MeshAccel accel(box, true);
    // Analytic: the face z = 1 lies 4 along this ray.
    CHECK(accel.occluded({0.2f, -0.3f, 5.f}, {0, 0, -1}, 0.f, 1e30f));
    CHECK_FALSE(accel.occluded({0.2f, -0.3f, 5.f}, {0, 0, -1}, 0.f, 3.9f));  // stops short
    CHECK_FALSE(accel.occluded({0.2f, -0.3f, 5.f}, {0, 0, 1}, 0.f, 1e30f));  // looks away
    CHECK_FALSE(accel.occluded({5, 5, 5}, {0, 0, 1}, 0.f, 1e30f));
    CHECK(accel.occluded({0, 0, 0}, {1, 0, 0}, 0.f, 1e30f));  // from inside
    // Random rays from inside and outside, with random ends: the same
    // answer as the closest hit's existence.
    SampleStream rng(7, 0, 0);
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
        const glm::vec3 o(4.f * rng.uniform() - 2.f, 4.f * rng.uniform() - 2.f, 4.f * rng.uniform() - 2.f);
        const glm::vec3 d = glm::normalize(glm::vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f));
        const float tmax = 4.f * rng.uniform();
        const bool hit = bool(accel.intersect_ray(o, d, 0.f, tmax));
        hits += hit;
        CHECK(accel.occluded(o, d, 0.f, tmax) == hit);
    }
    CHECK(hits > 400);  // both answers come up often (873 hits with this seed)
    CHECK(hits < 3600);
}

TEST_CASE("a packet of rays hits the box at the analytic distances and misses where it must",
          "[mesh_accel]") {
    const TriangleMesh box = unit_box();
    const MeshAccel accel(box, true);
    const glm::vec3 origin(0.3f, -0.2f, 4.f);
    SplitMix64 rng(3);
    for (int n = 0; n <= MeshAccel::kPacket; ++n) {
        glm::vec3 d[MeshAccel::kPacket];
        for (int i = 0; i < n; ++i) {  // toward points of the plane z = 0 in [-2, 2]²: some miss
            const glm::vec3 target(float(4 * rng.uniform() - 2), float(4 * rng.uniform() - 2), 0.f);
            d[i] = glm::normalize(target - origin);
        }
        std::optional<SurfaceHit> hits[MeshAccel::kPacket];
        accel.intersect_packet(origin, d, n, hits);
        for (int i = 0; i < n; ++i) {
            // The front face z = 1, entered where |x|, |y| ≤ 1 there.
            const float t = (1.f - origin.z) / d[i].z;
            const glm::vec3 p = origin + t * d[i];
            INFO("ray " << i << " of " << n << " meets z = 1 at " << p.x << ", " << p.y);
            if (std::abs(p.x) < 0.999f && std::abs(p.y) < 0.999f) {
                REQUIRE(hits[i]);
                CHECK(hits[i]->t == Approx(t).epsilon(1e-5));
                CHECK(hits[i]->geometric_normal == glm::vec3(0, 0, 1));
            } else if (std::abs(p.x) > 1.001f || std::abs(p.y) > 1.001f) {
                // It passes beside the front face: it may still cross a side
                // face, which the single-ray query answers the same.
                const auto one = accel.intersect(origin, d[i], 0.f, 1e30f);
                REQUIRE(bool(hits[i]) == bool(one));
                if (one) CHECK(hits[i]->t == one->t);
            }
        }
    }
    CHECK_THROWS(accel.intersect_packet(origin, nullptr, MeshAccel::kPacket + 1, nullptr));
}

TEST_CASE("no ray escapes the closed box, not even along the triangles' shared edges",
          "[mesh_accel]") {
    const TriangleMesh box = unit_box();
    const MeshAccel accel(box);
    SplitMix64 rng(8);
    for (int i = 0; i < 100000; ++i) {
        const glm::vec3 p(float(rng.uniform() * 1.8 - 0.9), float(rng.uniform() * 1.8 - 0.9),
                          float(rng.uniform() * 1.8 - 0.9));
        glm::vec3 d;
        if (i % 2 == 0) {  // uniform direction
            const double z = 1 - 2 * rng.uniform(), phi = 2 * 3.14159265358979 * rng.uniform();
            const double r = std::sqrt(1 - z * z);
            d = glm::vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
        } else {  // aimed at a face diagonal or a box edge: the seams
            const glm::vec3 on_seam = (i % 4 == 1) ? glm::vec3(0.37f, 0.37f, 1.f)
                                                   : glm::vec3(1.f, 1.f, float(rng.uniform() * 2 - 1));
            d = glm::normalize(on_seam - p);
        }
        const auto hit = accel.intersect(p, d, 0.f, 1e30f);
        REQUIRE(hit);
        REQUIRE(hit->t == Approx(exit_distance(p, d)).epsilon(1e-4));
        REQUIRE(glm::dot(hit->geometric_normal, d) > 0.f);  // leaving through the outside face
    }
}

TEST_CASE("the shading normal's derivatives match finite differences along the surface",
          "[mesh_accel]") {
    // On an icosphere with interpolated vertex normals, step from a hit
    // along each tangent of its triangle (staying inside the triangle) and
    // compare the change of the interpolated normal with the derivative.
    const TriangleMesh m = icosphere(2, 1.f);
    const MeshAccel accel(m);
    SampleStream rng(7, 0, 0);
    int checked = 0;
    for (int i = 0; i < 200; ++i) {
        const float z = 2.f * rng.uniform() - 1.f, phi = 6.2831853f * rng.uniform();
        const float s = std::sqrt(std::max(0.f, 1.f - z * z));
        const glm::vec3 dir(s * std::cos(phi), s * std::sin(phi), z);
        const auto hit = accel.intersect({0, 0, 0}, dir, 0.f, 10.f);
        REQUIRE(hit);
        const SurfaceDifferential sd = accel.differential(*hit);
        CHECK(std::abs(glm::dot(sd.tangent[0], hit->geometric_normal)) < 1e-5f);
        CHECK(std::abs(glm::dot(sd.tangent[1], hit->geometric_normal)) < 1e-5f);
        CHECK(std::abs(glm::dot(sd.tangent[0], sd.tangent[1])) < 1e-5f);
        const glm::vec3 y = hit->t * dir;
        for (int k = 0; k < 2; ++k) {
            const float h = 1e-3f;
            // The neighbour, found by a ray through it from the centre (the
            // same triangle for points well inside it).
            const glm::vec3 q = y + h * sd.tangent[k];
            const auto hq = accel.intersect({0, 0, 0}, glm::normalize(q), 0.f, 10.f);
            REQUIRE(hq);
            if (hq->primitive != hit->primitive || std::abs(hq->t - glm::length(q)) > 1e-5f) continue;
            const glm::vec3 fd = (hq->shading_normal - hit->shading_normal) / h;
            INFO("derivative " << sd.dn[k].x << " " << sd.dn[k].y << " " << sd.dn[k].z
                               << ", difference quotient " << fd.x << " " << fd.y << " " << fd.z);
            // The normal turns by about 1 per unit length on a unit sphere;
            // the quotient's error is O(h) plus float rounding / h.
            CHECK(glm::length(fd - sd.dn[k]) < 0.02f);
            CHECK(glm::length(sd.dn[k]) > 0.5f);
            ++checked;
        }
    }
    CHECK(checked > 300);
    // Flat shading: the normal does not vary.
    const MeshAccel flat(m, true);
    const auto hit = flat.intersect({0, 0, 0}, glm::normalize(glm::vec3(0.2f, 0.5f, 0.8f)), 0.f, 10.f);
    REQUIRE(hit);
    const SurfaceDifferential sd = flat.differential(*hit);
    CHECK(sd.dn[0] == glm::vec3(0.f));
    CHECK(sd.dn[1] == glm::vec3(0.f));
}

TEST_CASE("the distance to the surface is the box's analytic distance, inside and out", "[mesh_accel]") {
    // Inside [-1, 1]³ the nearest surface point lies on the nearest face:
    // distance 1 − max|p_k|. Outside it is the length of p's excess over the
    // box (a face, an edge or a corner: every Voronoi region of a triangle).
    const TriangleMesh box = unit_box();
    const MeshAccel accel(box);
    SplitMix64 rng(7);
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 p(4.f * float(rng.uniform()) - 2.f, 4.f * float(rng.uniform()) - 2.f,
                          4.f * float(rng.uniform()) - 2.f);
        const glm::vec3 a = glm::abs(p);
        const float inside = 1.f - std::max(a.x, std::max(a.y, a.z));
        const float expected =
            inside >= 0.f ? inside : glm::length(glm::max(a - glm::vec3(1.f), glm::vec3(0.f)));
        INFO("p = " << p.x << " " << p.y << " " << p.z);
        CHECK(accel.distance_to_surface(p, 10.f) == Approx(expected).margin(1e-5));
        // No triangle within a smaller radius: the radius itself comes back.
        CHECK(accel.distance_to_surface(p, 0.5f * expected) == Approx(0.5f * expected).margin(1e-6));
    }
}
