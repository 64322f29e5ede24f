#pragma once
// Sampling warps shared by the phase functions, the lights and the light
// estimators: uniform numbers in [0, 1)² → directions, with their densities.

#include <glm/vec3.hpp>

namespace jade {

// A right-handed orthonormal frame (b1, b2, n) around unit vector n
// (Duff et al. 2017, "Building an orthonormal basis, revisited").
void orthonormal_basis(const glm::vec3& n, glm::vec3& b1, glm::vec3& b2);

// Direction uniform in solid angle over the cone of unit `axis` with half-angle
// acos(cos_max), cos_max < 1; and that density, 1 / (2π (1 − cos_max)).
glm::vec3 uniform_cone(const glm::vec3& axis, float cos_max, float u1, float u2);
float uniform_cone_pdf(float cos_max);

}  // namespace jade
