// The clearance grid against exact distances: it must never exceed the
// distance to the surface (a flight it lets through must not cross the
// boundary), and it should not be much below it.

#include "jade/geometry/clearance_grid.h"
#include "jade/core/random.h"

#include <catch2/catch.hpp>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

using namespace jade;

namespace {

// Distance from p to segment ab.
float segment_distance(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b) {
    const glm::vec3 ab = b - a;
    const float t = glm::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.f, 1.f);
    return glm::length(p - (a + t * ab));
}

// Exact distance from p to triangle abc: to its plane when p projects inside
// it, else to the nearest edge (brute force, independent of the grid's code).
float triangle_distance(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    const glm::vec3 q = p - glm::dot(p - a, n) * n;
    const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0.f &&
                        glm::dot(glm::cross(c - b, q - b), n) >= 0.f &&
                        glm::dot(glm::cross(a - c, q - c), n) >= 0.f;
    if (inside) return std::abs(glm::dot(p - a, n));
    return std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

float mesh_distance(const TriangleMesh& m, const glm::vec3& p) {
    float d = 1e30f;
    for (const auto& t : m.triangles)
        d = std::min(d, triangle_distance(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]));
    return d;
}

TriangleMesh box_mesh(glm::vec3 half) {  // [-half, half], two triangles a face
    TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back(half * glm::vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

}  // namespace

TEST_CASE("clearance never exceeds the distance to the surface, and is close to it",
          "[clearance]") {
    struct Case {
        const char* name;
        TriangleMesh mesh;
    };
    // A flat box (large triangles, long thin cells of samples) and a sphere.
    const Case cases[] = {{"box", box_mesh({1.f, 0.4f, 0.7f})}, {"sphere", icosphere(3, 1.f)}};
    for (const Case& k : cases) {
        SECTION(k.name) {
            const ClearanceGrid grid(k.mesh, 32);
            const Bounds3 b = k.mesh.bounds();
            SampleStream rng(7, 0, 0);
            int deep = 0;
            for (int i = 0; i < 4000; ++i) {
                // Inside and around the box, beyond the grid's padding too.
                const glm::vec3 u(rng.uniform(), rng.uniform(), rng.uniform());
                const glm::vec3 p = b.min - 0.2f * b.extent() + 1.4f * u * b.extent();
                const float exact = mesh_distance(k.mesh, p);
                const float bound = grid.at(p);
                REQUIRE(bound >= 0.f);
                REQUIRE(bound <= exact);
                // At most the loss the construction allows: the transform
                // may be off by a sample spacing (3/4 cell) and a half
                // diagonal either way, a quarter cell of rounding, and the
                // step from the cell's centre counts twice (a diagonal).
                if (bound > 0.f) {
                    const float loss = 2.f * (0.75f + 0.5f * std::sqrt(3.f)) + 0.25f + std::sqrt(3.f);
                    CHECK(exact - bound <= loss * grid.cell_size() + 1e-5f);
                    ++deep;
                }
            }
            CHECK(deep > 500);  // the bound is useful, not 0 everywhere
        }
    }
}

TEST_CASE("an empty or degenerate mesh has no clearance", "[clearance]") {
    const ClearanceGrid empty(TriangleMesh{}, 32);
    CHECK(empty.at({0, 0, 0}) == 0.f);
    TriangleMesh point;
    point.positions = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
    point.triangles = {{0, 1, 2}};
    const ClearanceGrid grid(point, 32);
    CHECK(grid.at({1, 1, 1}) == 0.f);
    CHECK(grid.at({std::nanf(""), 0, 0}) == 0.f);
}
