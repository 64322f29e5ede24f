#pragma once
// The participating medium inside the object (paper §5.1–5.2): scattering and
// absorption coefficients per RGB channel and per world unit at every point,
// and a majorant that bounds the extinction everywhere, for delta tracking.
// Variants live in jade/media/: homogeneous, and dense grids (the material
// volume's levels, or float grids from a foreign .vdb).

#include "jade/core/spectrum.h"

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
    // Memory the medium holds for its coefficients (benchmarks report it).
    virtual std::size_t memory_bytes() const = 0;
};

}  // namespace jade
