#pragma once
// Phase functions of the medium (paper §5.2, DESIGN §5). Directions are
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
    // Value (= pdf) for propagation directions `in` and `out` (unit vectors).
    float eval(const glm::vec3& in, const glm::vec3& out) const;
    // Outgoing direction for incoming `in` from two uniform numbers in [0, 1).
    glm::vec3 sample(const glm::vec3& in, float u1, float u2) const;

private:
    float g_;
};

// Uniform direction on the unit sphere; and a right-handed orthonormal frame
// around a unit vector (Duff et al. 2017), shared by the samplers.
glm::vec3 uniform_sphere(float u1, float u2);
void orthonormal_basis(const glm::vec3& n, glm::vec3& b1, glm::vec3& b2);

// Direction uniform in solid angle over the cone of unit `axis` with half-angle
// acos(cos_max), cos_max < 1; and that density, 1 / (2π (1 − cos_max)).
glm::vec3 uniform_cone(const glm::vec3& axis, float cos_max, float u1, float u2);
float uniform_cone_pdf(float cos_max);

}  // namespace jade
