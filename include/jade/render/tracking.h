#pragma once
// One tracking loop for every ray through the medium (in the spirit of
// pbrt-v4's SampleT_maj): tentative collisions are drawn against the
// medium's majorant segments, and a callback decides at each what happens —
// delta tracking (a real collision ends the flight) for paths, ratio
// tracking (every collision is null and weighs the estimate) for shadow
// rays. Free flights are exponential, so a flight's optical depth, drawn
// once, is spent across segments of different majorants without bias.

#include "jade/core/random.h"
#include "jade/render/majorant_grid.h"
#include "jade/render/medium.h"
#include "jade/render/scene.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>

namespace jade {

// Event counts of a set of paths (summed over threads; integers, so sums are
// exact and deterministic).
struct PathCounters {
    std::uint64_t paths = 0;
    std::uint64_t real_collisions = 0;  // absorption and scattering events
    std::uint64_t null_collisions = 0;  // rejected tentative collisions
    std::uint64_t surface_events = 0;   // reflections and refractions at the boundary
    std::uint64_t shadow_rays = 0;
    std::uint64_t manifold_walks = 0;     // Newton solves for a refraction toward the light
    std::uint64_t manifold_failures = 0;  // of which did not converge (light not found)
    std::uint64_t manifold_probes_ended = 0;  // delta-light walks ended after their probe (probe_survival)
    std::uint64_t capped_paths = 0;     // stopped by max_depth (a bias)
    std::uint64_t sphere_walks = 0;     // runs of collisions taken at once (their collisions are real_collisions)
    std::uint64_t vertices() const { return real_collisions + surface_events; }
    PathCounters& operator+=(const PathCounters& o);
};

// Crossings of an index-matched boundary are not interactions; a ray passing
// through more than this many surfaces is caught in a degenerate mesh.
constexpr int kMaxCrossings = 4096;

// Free-flight distance to the next tentative collision against majorant mu,
// from uniform u (the exponential optical depth at mu = 1). A uniform number is a multiple
// of 2^-24 below 1 (render/pixel_sampler.h's too), so 1 − u is exact and
// −log(1 − u) loses nothing to log1p(−u), which costs about twice as much.
inline float free_flight(float mu, float u) { return -std::log(1.f - u) / mu; }

// exp(−μ·Δt) per channel; a channel with a zero majorant is not attenuated,
// even over an infinite stretch.
inline Spectrum majorant_transmittance(const Spectrum& mu, float dt) {
    Spectrum T(1.f);
    for (int c = 0; c < 3; ++c)
        if (mu[c] > 0.f) T[c] = std::exp(-mu[c] * dt);
    return T;
}

// T_maj / T_maj[h] over dt, the weight a flight drawn by channel h's
// majorant gives each channel: one exponential of the majorants'
// difference per other channel, and exactly 1 for h.
inline Spectrum majorant_transmittance_ratio(const Spectrum& mu, float dt, int h) {
    Spectrum ratio(1.f);
    for (int c = 0; c < 3; ++c)
        if (c != h && mu[c] != mu[h]) ratio[c] = std::exp((mu[h] - mu[c]) * dt);
    return ratio;
}

// Which majorant channel draws the tentative collisions: a path's hero
// channel (its own majorant, so a homogeneous medium has no null collisions
// in it; Kutz et al. 2017, spectral tracking as in pbrt-v4 and Mitsuba), or
// the largest of the three (a grey majorant, for ratio tracking).
constexpr int kGreyMajorant = -1;

// The tentative collisions of one ray o + t·d (t ≥ 0), drawn against the
// majorant of `channel` less `control`, a control extinction σ_c ≤ σ_t
// (zero for delta tracking; the minorant for residual ratio tracking), and
// tracked stretch by stretch: track_to(t_to, ...) covers [where the last
// call stopped, t_to). At each tentative collision
// `collide(p, properties, sigma_maj, T_maj)` returns true to go on, false to
// stop; T_maj is the majorant transmittance per channel since the previous
// tentative collision (all ones under a grey majorant). Stretches where the
// channel's majorant is 0 (or all control) are crossed without drawing a
// number.
//
// One exponential optical depth is drawn per tentative collision and spent
// across the segments and stretches it passes (inverting the piecewise-
// constant majorant's optical depth: as exact as drawing anew in each, which
// free flights' memorylessness also allows, but without a logarithm per
// majorant cell or per clearance stretch), and the other channels' optical
// depths are summed and turned into transmittances only where a collision
// or the caller needs them: a majorant grid's cells are short, and a
// segment crossed costs additions.
class MajorantTracker {
public:
    MajorantTracker(const Medium& medium, const glm::vec3& o, const glm::vec3& d, int channel,
                    const Spectrum& control)
        : medium_(medium), o_(o), d_(d), control_(control), channel_(channel),
          segments_(medium.majorant_grid(), medium.majorant(), o, d) {}

    // False when a callback stopped the ray.
    template <typename Collide>
    bool track_to(float t_to, SampleStream& rng, Collide&& collide);
    // The majorant transmittance since the last tentative collision.
    Spectrum transmittance() const {
        Spectrum T(1.f);
        for (int c = 0; c < 3; ++c)
            if (tau_[c] > 0.f) T[c] = std::exp(-tau_[c]);
        return T;
    }

private:
    bool grey() const { return channel_ == kGreyMajorant; }
    void add_depth(const Spectrum& mu, float dt) {
        for (int c = 0; c < 3; ++c)
            if (mu[c] > 0.f) tau_[c] += mu[c] * dt;  // a zero majorant attenuates nothing
    }

    const Medium& medium_;
    glm::vec3 o_, d_;
    Spectrum control_;
    int channel_;
    MajorantIterator segments_;
    Spectrum tau_{0.f};   // majorant optical depth since the last tentative collision (not grey)
    float to_go_ = -1.f;  // the drawn optical depth still to cover; < 0: none drawn
};

template <typename Collide>
bool MajorantTracker::track_to(float t_to, SampleStream& rng, Collide&& collide) {
    for (MajorantSegment seg; segments_.next(seg, t_to);) {
        const Spectrum residual = glm::max(Spectrum(0.f), seg.sigma_maj - control_);
        const Spectrum mu = grey() ? Spectrum(max_component(residual)) : residual;
        const float rate = mu[grey() ? 0 : channel_];
        float t = seg.t_min;
        if (rate > 0.f) {
            for (;;) {
                if (to_go_ < 0.f) to_go_ = free_flight(1.f, rng.uniform());
                const float next = t + to_go_ / rate;
                if (!(next < seg.t_max)) {
                    to_go_ = std::max(0.f, to_go_ - rate * (seg.t_max - t));
                    break;
                }
                to_go_ = -1.f;
                if (!grey()) add_depth(mu, next - t);
                t = next;
                const glm::vec3 p = o_ + t * d_;
                if (!collide(p, medium_.at(p), mu, grey() ? Spectrum(1.f) : transmittance())) return false;
                tau_ = Spectrum(0.f);
            }
        }
        if (!grey()) add_depth(mu, seg.t_max - t);
    }
    return true;
}

// The tentative collisions of o + t·d for 0 ≤ t < t_max as MajorantTracker
// draws them. Returns the majorant transmittance from the last tentative
// collision to t_max, or zero when a callback stopped the flight.
template <typename Collide>
Spectrum sample_t_maj(const Medium& medium, const glm::vec3& o, const glm::vec3& d, float t_max,
                      int channel, const Spectrum& control, SampleStream& rng, Collide&& collide) {
    MajorantTracker tracker(medium, o, d, channel, control);
    if (!tracker.track_to(t_max, rng, collide)) return Spectrum(0.f);
    return tracker.transmittance();
}

// Sphere tracing through the boundary's clearance: the start of a ray from o
// along d is cut into stretches that provably stay inside the surface's
// clearance, and `stretch(r)` tracks each (length r from o), returning false
// to stop. o advances past every stretch tracked to its end. Returns true
// when the caller must go on to the boundary with a ray query from o.
constexpr int kMaxClearanceSteps = 8;
template <typename Stretch>
bool advance_within_clearance(const Boundary& boundary, glm::vec3& o, const glm::vec3& d,
                              Stretch&& stretch) {
    for (int step = 0; step < kMaxClearanceSteps; ++step) {
        const float r = boundary.clearance(o);
        // Near the surface (or no grid: a degenerate mesh): ask Embree.
        if (!(r > 0.f) || r < boundary.clearance_resolution()) break;
        if (!stretch(r)) return false;
        o += r * d;
    }
    return true;
}

// Residual ratio tracking (Novák et al. 2014) along o + t·d for
// 0 ≤ t < t_max: the estimate starts at the transmittance of the medium's
// minorant σ_c, known in closed form, and every tentative collision, drawn
// against the residual majorant μ − σ_c, multiplies it by the probability
// of a null collision of the residual there, 1 − (σ_t − σ_c) / (μ − σ_c),
// per channel; Russian roulette ends a faint estimate without bias. Where
// the extinction is the same everywhere (the default model: σ_t = d_s + k_s
// in every voxel at d_a = 1, docs/design.md, "Coefficients") the residual
// is zero: the transmittance is exact and needs no lookup. Plain ratio tracking (Cramer 1978) against a
// majorant equal to σ_t would instead answer 0 or 1.
Spectrum ratio_tracking(const Medium& medium, const glm::vec3& o, const glm::vec3& d, float t_max,
                        SampleStream& rng, PathCounters& counters);

// Transmittance from a medium vertex `origin` toward `direction` out of the
// scene, through every stretch of medium the ray crosses (the boundary
// treated as index-matched). Unbiased per channel.
Spectrum transmittance(const Scene& scene, const glm::vec3& origin, const glm::vec3& direction,
                       SampleStream& rng, PathCounters& counters);

}  // namespace jade
