#pragma once
// Exits of random walks from spheres of homogeneous, non-absorbing medium
// (docs/stiff-media.md): whole runs of collisions taken at once where a
// path's next thousands of collisions would stay in a ball of one medium.
//
// A walk starts at a sphere's centre, flying along +z (a free flight is
// memoryless, so "just scattered into +z" and "in flight along +z" are the
// same start), with unit extinction and the scene's phase function, and
// goes on until it crosses the sphere. What a renderer needs of it is
// where and in which direction it leaves, how many times it scattered and
// how far it travelled: absorption and every channel's weight follow from
// the count and the length in closed form (integrator.h). The process is
// symmetric about its initial direction, so an outcome turned by a random
// angle about the path's direction is an outcome of the path's own walk.
//
// A table holds such outcomes for spheres of radius R₀·2^k mean free paths
// (Moon et al. 2007 tabulate the same exits as "shell transport
// functions"). Each outcome is a whole walk, not a histogram bin: sampling
// a stored outcome uniformly draws from the walk's exact distribution,
// with nothing binned, interpolated or fitted. Level 0 is simulated
// collision by collision; a walk in level k's sphere jumps through the
// largest smaller sphere that fits around its current point (walk on
// spheres, Muller 1956), so every level costs about the same to build.
//
// What a finite table costs: the draws of one render share its outcomes,
// so the image carries an error of the order of one outcome's spread over
// √(outcomes) that more samples per pixel do not average out; renders with
// different seeds build different tables, and that error is then part of
// the difference between two seeds. docs/stiff-media.md measures it.

#include "jade/render/phase_function.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace jade {

// One walk from a sphere's centre to its surface, in the frame whose +z is
// the walk's initial direction, lengths in mean free paths.
struct SphereExit {
    double collisions = 0.0;   // scattering events inside the sphere
    double path_length = 0.0;  // distance travelled, the last flight up to the surface included
    glm::vec3 point{0.f};      // where it leaves, on the unit sphere
    glm::vec3 direction{0.f};  // the direction it leaves in
};

class SphereExitTables {
public:
    // Radius of level 0 in mean free paths: a sphere smaller than this saves
    // fewer collisions than its look-up costs.
    static constexpr double kSmallestRadius = 4.0;
    static constexpr int kOutcomesPerLevel = 1 << 16;

    SphereExitTables() = default;  // no levels: nothing is taken at once
    // Levels up to the largest radius ≤ max_radius (mean free paths), for
    // `phase`; deterministic for a seed (built in parallel).
    SphereExitTables(const PhaseFunction& phase, double max_radius, std::uint64_t seed,
                     int outcomes_per_level = kOutcomesPerLevel);

    int levels() const { return int(levels_.size()); }
    static double radius(int level);
    // The largest level whose sphere fits in `optical_radius` (mean free
    // paths), or -1 when even level 0 does not.
    int level_for(double optical_radius) const;
    // Outcome of level `level` for a uniform number u in [0, 1).
    const SphereExit& sample(int level, double u) const;
    std::size_t memory_bytes() const;

    // Walks built side by side by a thread, so that their reads of the
    // tables overlap (docs/stiff-media.md).
    static constexpr int kLanes = 16;

private:
    struct Walker;
    void walk(int level, const std::uint64_t* streams, int count, SphereExit* outcomes) const;
    bool step(Walker& w, double R) const;
    PhaseFunction phase_;
    std::vector<std::vector<SphereExit>> levels_;
};

// Where an outcome lands in the world: its frame's +z is the path's unit
// direction `axis`, turned about it by the angle whose cosine and sine are
// given. Made once for an outcome's point and direction both.
class SphereExitFrame {
public:
    SphereExitFrame(const glm::vec3& axis, float cos_phi, float sin_phi);
    // A point or direction of the outcome, in the world.
    glm::vec3 to_world(const glm::vec3& local) const;

private:
    glm::vec3 t_, b_, axis_;
    float cos_phi_, sin_phi_;
};

}  // namespace jade
