#include "jade/render/sphere_exit.h"

#include "jade/core/error.h"
#include "jade/core/math.h"
#include "jade/core/random.h"
#include "jade/core/sampling.h"

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace jade {

namespace {
// A uniform double as a float strictly below 1 (a double just below 1
// rounds up to 1.f).
float below_one(double u) { return std::min(float(u), 0x1.fffffep-1f); }

// Where the walk at pos (inside a sphere of radius R about the origin)
// flying along unit d crosses the sphere.
double distance_to_sphere(const glm::dvec3& pos, const glm::dvec3& d, double R) {
    const double b = glm::dot(pos, d);
    const double c = glm::dot(pos, pos) - R * R;  // ≤ 0 inside
    return std::max(0.0, -b + std::sqrt(std::max(0.0, b * b - c)));
}
}  // namespace

glm::vec3 sphere_exit_to_world(const glm::vec3& local, const glm::vec3& axis, float cos_phi,
                               float sin_phi) {
    glm::vec3 t, b;
    orthonormal_basis(axis, t, b);
    const float x = cos_phi * local.x - sin_phi * local.y;
    const float y = sin_phi * local.x + cos_phi * local.y;
    return x * t + y * b + local.z * axis;
}

double SphereExitTables::radius(int level) { return std::ldexp(kSmallestRadius, level); }

SphereExitTables::SphereExitTables(const PhaseFunction& phase, double max_radius, std::uint64_t seed,
                                   int outcomes_per_level)
    : phase_(phase) {
    if (outcomes_per_level < 1) throw Error("internal: a sphere exit table needs outcomes");
    // 2^40 mean free paths is far beyond any float position's resolution.
    const double top = std::min(max_radius, std::ldexp(1.0, 40));
    for (int level = 0; radius(level) <= top; ++level) {
        std::vector<SphereExit> outcomes(static_cast<std::size_t>(outcomes_per_level));
        const std::uint64_t key = splitmix64(splitmix64(seed ^ 0x5851F42D4C957F2Dull) +
                                             std::uint64_t(level) * 0x9E3779B97F4A7C15ull);
        tbb::parallel_for(std::size_t(0), outcomes.size(), [&](std::size_t i) {
            outcomes[i] = walk(level, splitmix64(key + i));
        });
        levels_.push_back(std::move(outcomes));  // the next level walks through this one
    }
}

// One walk from the centre of level `level`'s sphere to its surface: a
// collision at a time where no smaller tabulated sphere fits around the
// walker, otherwise one jump through the largest that does.
SphereExit SphereExitTables::walk(int level, std::uint64_t stream) const {
    SplitMix64 rng(stream);
    const double R = radius(level);
    glm::dvec3 pos(0.0);
    glm::vec3 dir(0.f, 0.f, 1.f);
    SphereExit out;
    for (;;) {
        const int inner = level_for(R - glm::length(pos));  // only levels below this are built
        if (inner >= 0) {
            const SphereExit& e = sample(inner, rng.uniform());
            const double phi = 2.0 * kPiD * rng.uniform();
            const float c = float(std::cos(phi)), s = float(std::sin(phi));
            pos += radius(inner) * glm::dvec3(sphere_exit_to_world(e.point, dir, c, s));
            dir = glm::normalize(sphere_exit_to_world(e.direction, dir, c, s));
            out.collisions += e.collisions;
            out.path_length += e.path_length;
            continue;
        }
        const double to_surface = distance_to_sphere(pos, glm::dvec3(dir), R);
        const double flight = -std::log1p(-rng.uniform());
        if (flight >= to_surface) {
            pos += to_surface * glm::dvec3(dir);
            out.path_length += to_surface;
            out.point = glm::vec3(glm::normalize(pos));
            out.direction = dir;
            return out;
        }
        pos += flight * glm::dvec3(dir);
        out.path_length += flight;
        out.collisions += 1.0;
        const float u1 = below_one(rng.uniform()), u2 = below_one(rng.uniform());
        dir = phase_.sample(dir, u1, u2);
    }
}

int SphereExitTables::level_for(double optical_radius) const {
    if (!(optical_radius >= kSmallestRadius)) return -1;
    // The exponent of radius / R₀ is exact: no logarithm is rounded.
    return std::min(std::ilogb(optical_radius / kSmallestRadius), levels() - 1);
}

const SphereExit& SphereExitTables::sample(int level, double u) const {
    const std::vector<SphereExit>& outcomes = levels_[std::size_t(level)];
    const auto i = std::min(outcomes.size() - 1, std::size_t(u * double(outcomes.size())));
    return outcomes[i];
}

std::size_t SphereExitTables::memory_bytes() const {
    std::size_t bytes = 0;
    for (const auto& level : levels_) bytes += level.size() * sizeof(SphereExit);
    return bytes;
}

}  // namespace jade
