#pragma once
// The participating medium inside the object (paper §5.1–5.2): scattering and
// absorption coefficients per RGB channel and per world unit at every point,
// and a majorant that bounds the extinction everywhere, for delta tracking.
// Variants live in render/media/: homogeneous, and dense grids (the material
// volume's levels, or float grids from a foreign .vdb).
//
// Tracking (render/tracking.h) asks the medium for majorant segments along a
// ray: stretches with one majorant per channel each. Today's media hand out
// one segment with their global majorant; a medium with a majorant grid
// hands out one per cell it crosses, and no tracking loop changes.

#include "jade/core/spectrum.h"

#include <glm/vec3.hpp>

#include <cstddef>

namespace jade {

struct MediumProperties {
    Spectrum sigma_s{0.f};  // scattering coefficient
    Spectrum sigma_a{0.f};  // absorption coefficient
};

// A stretch [t_min, t_max) of a ray over which σ_t ≤ sigma_maj, per channel.
struct MajorantSegment {
    float t_min = 0.f, t_max = 0.f;
    Spectrum sigma_maj{0.f};
};

class Medium {
public:
    virtual ~Medium() = default;
    // Coefficients at world point p (any point: grids clamp to their edge).
    virtual MediumProperties at(const glm::vec3& p) const = 0;
    // Per-channel upper bound of σ_t = σ_s + σ_a over all points.
    virtual Spectrum majorant() const = 0;
    // Per-channel lower bound of σ_t over all points (0 where none is
    // known): the control extinction of residual ratio tracking
    // (render/tracking.h).
    virtual Spectrum minorant() const { return Spectrum(0.f); }
    // The segment of the ray o + t·d that starts at t_min and ends no later
    // than t_max. The default: all of [t_min, t_max) under the global
    // majorant.
    virtual MajorantSegment majorant_segment(const glm::vec3& o, const glm::vec3& d, float t_min,
                                             float t_max) const;
    // The same coefficients at every point: a path may then take whole runs
    // of collisions at once (render/sphere_exit.h).
    virtual bool homogeneous() const { return false; }
    // Memory the medium holds for its coefficients (benchmarks report it).
    virtual std::size_t memory_bytes() const = 0;
};

}  // namespace jade
