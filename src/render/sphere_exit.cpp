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

SphereExitFrame::SphereExitFrame(const glm::vec3& axis, float cos_phi, float sin_phi)
    : axis_(axis), cos_phi_(cos_phi), sin_phi_(sin_phi) {
    orthonormal_basis(axis, t_, b_);
}

glm::vec3 SphereExitFrame::to_world(const glm::vec3& local) const {
    const float x = cos_phi_ * local.x - sin_phi_ * local.y;
    const float y = sin_phi_ * local.x + cos_phi_ * local.y;
    return x * t_ + y * b_ + local.z * axis_;
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
        tbb::parallel_for(std::size_t(0), outcomes.size(), std::size_t(kLanes), [&](std::size_t first) {
            const int count = int(std::min<std::size_t>(kLanes, outcomes.size() - first));
            std::uint64_t streams[kLanes];
            for (int i = 0; i < count; ++i) streams[i] = splitmix64(key + first + std::size_t(i));
            walk(level, streams, count, &outcomes[first]);
        });
        levels_.push_back(std::move(outcomes));  // the next level walks through this one
    }
}

// A walk in progress: where it is, where it flies, what it has done, and
// the tabulated outcome its next jump takes (drawn, not yet read).
struct SphereExitTables::Walker {
    SplitMix64 rng{0};
    glm::dvec3 pos{0.0};
    glm::vec3 dir{0.f, 0.f, 1.f};
    SphereExit out;
    int inner = -1;                    // the level of that jump; −1 for a collision
    const SphereExit* jump = nullptr;  // its outcome
    bool done = false;
};

// Walks from the centre of level `level`'s sphere to its surface, one per
// stream, `count` (at most kLanes) of them side by side: a collision at a
// time where no smaller tabulated sphere fits around the walker, otherwise
// one jump through the largest that does. A jump reads an outcome at a
// random place in tables of megabytes, and a walk waits for each such read
// before its next step: so every walker draws its outcome and asks for it
// (a prefetch) before any reads one, and the reads of all lanes overlap
// (the build is bound by memory latency; docs/stiff-media.md). Each
// walker's own steps are those of a lone walk, draw for draw.
void SphereExitTables::walk(int level, const std::uint64_t* streams, int count, SphereExit* outcomes) const {
    const double R = radius(level);
    Walker lanes[kLanes];
    for (int i = 0; i < count; ++i) lanes[i].rng = SplitMix64(streams[i]);
    for (int left = count; left > 0;) {
        for (int i = 0; i < count; ++i) {
            Walker& w = lanes[i];
            if (w.done) continue;
            w.inner = level_for(R - glm::length(w.pos));  // only levels below this are built
            w.jump = w.inner >= 0 ? &sample(w.inner, w.rng.uniform()) : nullptr;
            if (w.jump) __builtin_prefetch(w.jump);
        }
        for (int i = 0; i < count; ++i) {
            Walker& w = lanes[i];
            if (w.done || step(w, R)) continue;
            outcomes[i] = w.out;
            w.done = true;
            --left;
        }
    }
}

// The walker's next step: its drawn jump, or a flight to a collision or
// out of the sphere of radius R (false: it left).
bool SphereExitTables::step(Walker& w, double R) const {
    if (w.jump) {
        const SphereExit& e = *w.jump;
        const double phi = 2.0 * kPiD * w.rng.uniform();
        const float c = float(std::cos(phi)), s = float(std::sin(phi));
        const SphereExitFrame frame(w.dir, c, s);
        w.pos += radius(w.inner) * glm::dvec3(frame.to_world(e.point));
        w.dir = glm::normalize(frame.to_world(e.direction));
        w.out.collisions += e.collisions;
        w.out.path_length += e.path_length;
        return true;
    }
    const double to_surface = distance_to_sphere(w.pos, glm::dvec3(w.dir), R);
    const double flight = -std::log1p(-w.rng.uniform());
    if (flight >= to_surface) {
        w.pos += to_surface * glm::dvec3(w.dir);
        w.out.path_length += to_surface;
        w.out.point = glm::vec3(glm::normalize(w.pos));
        w.out.direction = w.dir;
        return false;
    }
    w.pos += flight * glm::dvec3(w.dir);
    w.out.path_length += flight;
    w.out.collisions += 1.0;
    const float u1 = below_one(w.rng.uniform()), u2 = below_one(w.rng.uniform());
    w.dir = phase_.sample(w.dir, u1, u2);
    return true;
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
