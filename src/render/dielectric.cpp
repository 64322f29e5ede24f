#include "jade/render/dielectric.h"

#include "jade/core/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace jade {

const char* to_string(BoundaryMode mode) {
    switch (mode) {
    case BoundaryMode::Split: return "split";
    case BoundaryMode::Fresnel: return "fresnel";
    case BoundaryMode::None: return "none";
    }
    return "?";
}

BoundaryMode parse_boundary_mode(const std::string& name) {
    if (name == "split") return BoundaryMode::Split;
    if (name == "fresnel") return BoundaryMode::Fresnel;
    if (name == "none") return BoundaryMode::None;
    throw Error("--boundary must be 'split', 'fresnel' or 'none', not '" + name + "'");
}

void BoundaryParams::validate() const {
    if (!(ior >= 1.f && ior <= 4.f)) throw Error("--ior must lie between 1 and 4");
    if (!(specular >= 0.f && specular <= 1.f)) throw Error("--specular must lie between 0 and 1");
}

float fresnel_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    const float sin2_t = (1.f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.f) return 1.f;
    const float cos_t = std::sqrt(1.f - sin2_t);
    const float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parallel * r_parallel + r_perp * r_perp);
}

glm::vec3 reflect(const glm::vec3& d, const glm::vec3& n) { return d - 2.f * glm::dot(d, n) * n; }

bool refract(const glm::vec3& d, const glm::vec3& n, float eta, glm::vec3& out) {
    const float cos_i = -glm::dot(d, n);
    const float sin2_t = (1.f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.f) return false;
    const float cos_t = std::sqrt(1.f - sin2_t);
    out = glm::normalize(d / eta + (cos_i / eta - cos_t) * n);
    return true;
}

BoundaryTransmission boundary_transmission(const BoundaryParams& p, const glm::vec3& d,
                                           const glm::vec3& normal, bool entering) {
    const glm::vec3 n = glm::dot(d, normal) < 0.f ? normal : -normal;  // faces the incoming side
    const float eta = entering ? p.ior : 1.f / p.ior;
    BoundaryTransmission t;
    if (!refract(d, n, eta, t.direction)) return {};
    t.weight = 1.f - (p.mode == BoundaryMode::Fresnel ? fresnel_dielectric(-glm::dot(d, n), eta)
                                                      : p.specular);
    return t;
}

glm::vec3 interface_normal(const SurfaceHit& hit, const glm::vec3& d, bool entering) {
    return (glm::dot(d, hit.shading_normal) < 0.f) == entering ? hit.shading_normal
                                                               : hit.geometric_normal;
}

bool on_sampled_side(const glm::vec3& d_in, const glm::vec3& d_out, const glm::vec3& ng, bool reflected) {
    const bool from_outside = glm::dot(d_in, ng) < 0.f;
    const float side = glm::dot(d_out, ng);  // > 0: outward; 0 (along the triangle): neither side
    const bool outward = from_outside == reflected;
    return outward ? side > 0.f : side < 0.f;
}

BoundarySample sample_boundary(const BoundaryParams& p, const glm::vec3& d, const glm::vec3& normal,
                               bool entering, float u) {
    const BoundaryTransmission t = boundary_transmission(p, d, normal, entering);
    const float p_reflect = 1.f - t.weight;  // 1 under total internal reflection
    if (u < p_reflect) {
        const glm::vec3 n = glm::dot(d, normal) < 0.f ? normal : -normal;
        return {reflect(d, n), true};
    }
    return {t.direction, false};
}

}  // namespace jade
