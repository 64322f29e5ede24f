#pragma once
// The participating medium inside the object (paper §5.1–5.2): scattering and
// absorption coefficients per RGB channel and per world unit at every point,
// and a majorant that bounds the extinction everywhere, for delta tracking.
// Variants live in render/media/: homogeneous, and dense grids (the material
// volume's levels, or float grids from a foreign .vdb).
//
// Tracking (render/tracking.h) walks majorant segments along a ray
// (render/majorant_grid.h): stretches with one majorant per channel each, the
// cells of the medium's majorant grid where it has one (the float grids of a
// foreign .vdb), else one stretch under its global majorant.

#include "jade/core/spectrum.h"
#include "jade/render/majorant_grid.h"

#include <glm/vec3.hpp>

#include <cstddef>

namespace jade {

struct MediumProperties {
    Spectrum sigma_s{0.f};  // scattering coefficient
    Spectrum sigma_a{0.f};  // absorption coefficient
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
    // The grid of local majorants tracking walks, if the medium has one;
    // without, tracking draws against majorant() all along.
    virtual const MajorantGrid* majorant_grid() const { return nullptr; }
    // The same coefficients at every point: a path may then take whole runs
    // of collisions at once (render/sphere_exit.h).
    virtual bool homogeneous() const { return false; }
    // Memory the medium holds for its coefficients (benchmarks report it).
    virtual std::size_t memory_bytes() const = 0;
};

}  // namespace jade
