#include "jade/phase_function.h"

#include "jade/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace jade {

namespace {
constexpr float kPi = 3.14159265358979323846f;
constexpr float kInv4Pi = 1.f / (4.f * kPi);
// Below this |g| the HG inversion loses precision; the isotropic formulas are
// exact there to O(g).
constexpr float kIsotropicG = 1e-3f;
}  // namespace

PhaseFunction::PhaseFunction(float g) : g_(g) {
    if (!(g > -1.f && g < 1.f)) throw Error("--g must lie strictly between -1 and 1");
}

float PhaseFunction::eval(const glm::vec3& in, const glm::vec3& out) const {
    const float cos_theta = glm::dot(in, out);
    const float denom = 1.f + g_ * g_ - 2.f * g_ * cos_theta;
    return kInv4Pi * (1.f - g_ * g_) / (denom * std::sqrt(std::max(denom, 1e-12f)));
}

void orthonormal_basis(const glm::vec3& n, glm::vec3& b1, glm::vec3& b2) {
    const float sign = std::copysign(1.f, n.z);
    const float a = -1.f / (sign + n.z);
    const float b = n.x * n.y * a;
    b1 = glm::vec3(1.f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = glm::vec3(b, sign + n.y * n.y * a, -n.y);
}

glm::vec3 uniform_sphere(float u1, float u2) {
    const float z = 1.f - 2.f * u1;
    const float r = std::sqrt(std::max(0.f, 1.f - z * z));
    const float phi = 2.f * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

glm::vec3 uniform_cone(const glm::vec3& axis, float cos_max, float u1, float u2) {
    // cos θ uniform in [cos_max, 1] makes the density uniform in solid angle.
    const float cos_t = 1.f - u1 * (1.f - cos_max);
    const float sin_t = std::sqrt(std::max(0.f, 1.f - cos_t * cos_t));
    const float phi = 2.f * kPi * u2;
    glm::vec3 t, b;
    orthonormal_basis(axis, t, b);
    return glm::normalize(sin_t * std::cos(phi) * t + sin_t * std::sin(phi) * b + cos_t * axis);
}

float uniform_cone_pdf(float cos_max) { return 1.f / (2.f * kPi * (1.f - cos_max)); }

glm::vec3 PhaseFunction::sample(const glm::vec3& in, float u1, float u2) const {
    float cos_theta;
    if (std::abs(g_) < kIsotropicG) {
        cos_theta = 1.f - 2.f * u1;
    } else {
        // Inverse of HG's cumulative distribution in cos θ.
        const float s = (1.f - g_ * g_) / (1.f - g_ + 2.f * g_ * u1);
        cos_theta = (1.f + g_ * g_ - s * s) / (2.f * g_);
    }
    cos_theta = std::clamp(cos_theta, -1.f, 1.f);
    const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
    const float phi = 2.f * kPi * u2;
    glm::vec3 t, b;
    orthonormal_basis(in, t, b);
    return glm::normalize(sin_theta * std::cos(phi) * t + sin_theta * std::sin(phi) * b +
                          cos_theta * in);
}

}  // namespace jade
