#pragma once
// A medium with the same coefficients everywhere (the reference scenes A, B;
// flags --sigma-s/--sigma-a).

#include "jade/render/medium.h"

namespace jade {

class HomogeneousMedium final : public Medium {
public:
    HomogeneousMedium(const Spectrum& sigma_s, const Spectrum& sigma_a);  // throws if negative
    MediumProperties at(const glm::vec3&) const override { return props_; }
    Spectrum majorant() const override { return props_.sigma_s + props_.sigma_a; }
    Spectrum minorant() const override { return majorant(); }
    bool homogeneous() const override { return true; }
    std::size_t memory_bytes() const override { return sizeof(*this); }

private:
    MediumProperties props_;
};

}  // namespace jade
