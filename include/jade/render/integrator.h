#pragma once
// Unbiased volumetric path tracing (DESIGN §8) through the dielectric
// boundary and the medium inside it.
//
// Free flights are sampled by delta tracking (Woodcock et al. 1965) against
// one grey majorant μ̄ = max over channels and space of σ_t. RGB media are
// chromatic, so each path picks a hero channel uniformly and chooses its
// collision events (absorb / scatter / null) with that channel's
// probabilities; the path's weight for each channel is then combined across
// the three channels' sampling densities by one-sample MIS with the balance
// heuristic (spectral MIS: Wilkie et al. 2014; pbrt-v4's VolPathIntegrator,
// Mitsuba 3's volpathmis). The estimate is unbiased in every channel and
// bounded: no channel's weight exceeds 3.
//
// Lights: the environment is met by rays leaving the scene. The directional
// light is met by rays leaving the scene within its disc (angular radius > 0),
// unless the vertex before was a medium vertex with a free line of sight to
// the light (boundary `none`), which counts it by next-event estimation
// instead, its shadow-ray transmittance by ratio tracking (Cramer 1978;
// Novák et al. 2014). Behind a smooth dielectric no straight shadow ray can
// reach a light; there each scattering vertex instead sends one ray into a
// cone aimed so that it refracts out toward the light's disc, ratio-tracked to
// the surface and followed through it, and combines it with the paths that
// refract out by phase sampling through multiple importance sampling (see
// light_guide in integrator.cpp). A delta light (radius 0) cannot be reached
// that way: behind a dielectric it lights nothing inside.
//
// Paths end by absorption, Russian roulette (after `rr_depth` interactions,
// survival = throughput when below 1) or when they would make interaction
// max_depth + 1: the light reaching the first max_depth interactions is
// counted. A cap biases the image, so capped paths are counted for reports.

#include "jade/core/random.h"
#include "jade/render/scene.h"

#include <cstdint>

namespace jade {

struct IntegratorSettings {
    int max_depth = 4096;  // surface + medium interactions; counted when reached
    int rr_depth = 8;      // interactions before Russian roulette starts
    // Next-event estimation of the directional light through a smooth
    // boundary (with MIS). Off, the light inside is found only by paths that
    // happen to refract out into its disc: same mean, more noise (for tests
    // and benchmarks of the two strategies).
    bool light_through_boundary = true;
    void validate() const;
};

// Event counts of a set of paths (summed over threads; integers, so sums are
// exact and deterministic).
struct PathCounters {
    std::uint64_t paths = 0;
    std::uint64_t real_collisions = 0;  // absorption and scattering events
    std::uint64_t null_collisions = 0;  // rejected tentative collisions
    std::uint64_t surface_events = 0;   // reflections and refractions at the boundary
    std::uint64_t shadow_rays = 0;
    std::uint64_t capped_paths = 0;     // stopped by max_depth (a bias)
    std::uint64_t vertices() const { return real_collisions + surface_events; }
    PathCounters& operator+=(const PathCounters& o);
};

struct PathSample {
    Spectrum radiance{0.f};
    bool hit_object = false;  // the camera ray met the object (coverage)
};

// One camera path: radiance arriving at the camera along propagation
// direction `direction` (unit) from `origin`, which must lie outside the
// object. (film_x, film_y) in [0,1]² is where it crosses the film, for the
// background image.
PathSample trace_path(const Scene& scene, const IntegratorSettings& settings,
                      const glm::vec3& origin, const glm::vec3& direction, float film_x,
                      float film_y, SampleStream& rng, PathCounters& counters);

// Transmittance along a ray from `origin` toward `direction` out of the scene,
// estimated by ratio tracking through every stretch of medium it crosses
// (the boundary treated as index-matched). Unbiased per channel.
Spectrum transmittance(const Scene& scene, const glm::vec3& origin, const glm::vec3& direction,
                       SampleStream& rng, PathCounters& counters);

}  // namespace jade
