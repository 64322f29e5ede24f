#include "jade/render/phase_function.h"

#include "jade/core/error.h"
#include "jade/core/math.h"
#include "jade/core/sampling.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace jade {

namespace {
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
