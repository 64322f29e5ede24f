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
// HG's 1 + g² − 2g cos θ for unit directions in, out, as a sum of two
// non-negative terms: for g ≥ 0 (1 − g)² + 2g (1 − cos θ), for g < 0
// (1 + g)² − 2g (1 + cos θ), with 1 ∓ cos θ = |out ∓ in|² / 2 (exact for
// small angles, where a dot product rounds to 1). The textbook form cancels
// catastrophically as |g| → 1 in the lobe's direction, where it rounds to 0
// or below and the density to infinity or NaN.
float hg_denominator(float g, const glm::vec3& in, const glm::vec3& out) {
    if (g >= 0.f) {
        const glm::vec3 d = out - in;
        return (1.f - g) * (1.f - g) + g * glm::dot(d, d);
    }
    const glm::vec3 d = out + in;
    return (1.f + g) * (1.f + g) - g * glm::dot(d, d);
}
}  // namespace

PhaseFunction::PhaseFunction(float g) : g_(g) {
    if (!(g > -1.f && g < 1.f)) throw Error("--g must lie strictly between -1 and 1");
}

float PhaseFunction::eval(const glm::vec3& in, const glm::vec3& out) const {
    if (g_ == 0.f) return kInv4Pi;  // isotropic, the default: asked at every scattering
    const float denom = hg_denominator(g_, in, out);
    return kInv4Pi * (1.f - g_) * (1.f + g_) / (denom * std::sqrt(denom));
}

glm::vec3 PhaseFunction::sample(const glm::vec3& in, float u1, float u2) const {
    // x = 1 − cos θ of HG with |g| (a g < 0 lobe is its mirror image), from
    // the inverse of its cumulative distribution rearranged so that no term
    // cancels: with d = 1 − |g| + 2|g| u1 and s = (1 − g²) / d,
    // x = (1 − |g|)(1 − u1)(s + 1 − |g|) / d. The textbook
    // cos θ = (1 + g² − s²) / 2g loses every digit as |g| → 1.
    float x;
    if (g_ == 0.f) {  // isotropic: cos θ uniform
        x = 2.f * u1;
    } else {
        const float a = std::abs(g_);
        const float d = 1.f - a + 2.f * a * u1;
        const float s = (1.f - a) * (1.f + a) / d;
        x = std::clamp((1.f - a) * (1.f - u1) * (s + 1.f - a) / d, 0.f, 2.f);
    }
    const float sin_theta = std::sqrt(std::max(0.f, x * (2.f - x)));
    const float cos_theta = g_ < 0.f ? x - 1.f : 1.f - x;
    const float phi = 2.f * kPi * u2;
    glm::vec3 t, b;
    orthonormal_basis(in, t, b);
    return glm::normalize(sin_theta * std::cos(phi) * t + sin_theta * std::sin(phi) * b +
                          cos_theta * in);
}

}  // namespace jade
