#include "jade/core/sampling.h"

#include "jade/core/math.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace jade {

void orthonormal_basis(const glm::vec3& n, glm::vec3& b1, glm::vec3& b2) {
    const float sign = std::copysign(1.f, n.z);
    const float a = -1.f / (sign + n.z);
    const float b = n.x * n.y * a;
    b1 = glm::vec3(1.f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = glm::vec3(b, sign + n.y * n.y * a, -n.y);
}

glm::vec3 uniform_sphere(float u1, float u2) {
    // z uniform in [−1, 1] makes the density uniform in solid angle
    // (Archimedes' hat-box theorem).
    const float z = 1.f - 2.f * u1, r = std::sqrt(std::max(0.f, (1.f - z) * (1.f + z)));
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

float UniformCone::pdf(const glm::vec3& w) const {
    if (is_delta() || glm::dot(w, axis) < cos_max) return 0.f;
    return uniform_cone_pdf(cos_max);
}

glm::vec3 UniformCone::sample(float u1, float u2, float& pdf) const {
    if (is_delta()) {
        pdf = 1.f;
        return axis;
    }
    pdf = uniform_cone_pdf(cos_max);
    return uniform_cone(axis, cos_max, u1, u2);
}

float EllipticCone::pdf(const glm::vec3& w) const {
    const float c = glm::dot(w, axis);
    if (!(c > 0.f)) return 0.f;
    const float x = glm::dot(w, major) / (c * r_major), y = glm::dot(w, minor) / (c * r_minor);
    if (!(x * x + y * y <= 1.f)) return 0.f;
    return 1.f / (kPi * r_major * r_minor * c * c * c);
}

glm::vec3 EllipticCone::sample(float u1, float u2) const {
    // Uniform in the unit disc (radius √u1), stretched to the ellipse.
    const float rho = std::sqrt(u1), phi = 2.f * kPi * u2;
    return glm::normalize(axis + (r_major * rho * std::cos(phi)) * major + (r_minor * rho * std::sin(phi)) * minor);
}

bool systematic_selected(float offset, int k, float q) {
    const double x = double(offset) + double(k) * double(q);
    return x - std::floor(x) < double(q);
}

}  // namespace jade
