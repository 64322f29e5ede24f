#pragma once
// Phase functions of the medium (paper §5.2; docs/design.md, "Phase function"). Directions are
// propagation directions: cos θ = dot(incoming, outgoing), so g > 0 scatters
// forward. Both functions are sampled exactly: the sampling weight
// p(ω)/pdf(ω) is 1, and eval() returns the pdf for multiple importance sampling.

#include <glm/vec3.hpp>

namespace jade {

// Henyey–Greenstein (1941): p(cos θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}).
// g = 0 is the isotropic phase function 1/(4π), the paper's and the default.
class PhaseFunction {
public:
    explicit PhaseFunction(float g = 0.f);
    float g() const { return g_; }
    // g = 0: every direction equally likely, whatever the incoming one.
    bool isotropic() const { return g_ == 0.f; }
    // Value (= pdf) for propagation directions `in` and `out` (unit vectors).
    float eval(const glm::vec3& in, const glm::vec3& out) const;
    // Outgoing direction for incoming `in` from two uniform numbers in [0, 1).
    glm::vec3 sample(const glm::vec3& in, float u1, float u2) const;

private:
    float g_;
};


}  // namespace jade
