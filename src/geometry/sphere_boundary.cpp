#include "jade/geometry/sphere_boundary.h"

#include "jade/core/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace jade {

namespace {

// How far inside (as a share of r²) both ends of a segment must lie for
// the float test to skip the exact query: float's rounding of |p − c|² is
// some 1e-7 of it.
constexpr float kInsideMargin = 1e-4f;

float sign_of(float x) { return x < 0.f ? -1.f : 1.f; }

// The unit normal in two numbers (RayHit's u, v): its octahedral
// coordinates (Meyer et al. 2010), exact to a few float ulps and free of
// trigonometry, both ways.
void encode_octahedral(const glm::vec3& n, float& u, float& v) {
    const float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    u = n.x / l1;
    v = n.y / l1;
    if (n.z < 0.f) {
        const float fu = (1.f - std::abs(v)) * sign_of(u), fv = (1.f - std::abs(u)) * sign_of(v);
        u = fu;
        v = fv;
    }
}

glm::vec3 decode_octahedral(float u, float v) {
    glm::vec3 n(u, v, 1.f - std::abs(u) - std::abs(v));
    if (n.z < 0.f) {
        const float x = (1.f - std::abs(v)) * sign_of(u), y = (1.f - std::abs(u)) * sign_of(v);
        n.x = x;
        n.y = y;
    }
    return glm::normalize(n);
}

}  // namespace

SphereBoundary::SphereBoundary(const glm::vec3& centre, float radius) : centre_(centre), radius_(radius) {
    if (!(radius > 0.f) || !std::isfinite(radius) || !std::isfinite(centre.x) || !std::isfinite(centre.y) ||
        !std::isfinite(centre.z))
        throw Error("a sphere needs a finite centre and a positive radius");
    bounds_.min = centre - glm::vec3(radius);
    bounds_.max = centre + glm::vec3(radius);
    for (int k = 0; k < 8; ++k)
        corners_.push_back({k & 1 ? bounds_.max.x : bounds_.min.x, k & 2 ? bounds_.max.y : bounds_.min.y,
                            k & 4 ? bounds_.max.z : bounds_.min.z});
}

// The roots of |o + t·d − c|² = r² in double precision: h = r² − |q|², q the
// ray's closest approach to the centre, loses nothing when the ray passes
// far from it, and the root nearer 0 is taken as (|o − c|² − r²) / (the
// other), which keeps its digits where it is small (a ray leaving the
// surface) instead of cancelling −b against √h.
std::optional<RayHit> SphereBoundary::intersect_ray(const glm::vec3& o, const glm::vec3& d, float tmin,
                                                    float tmax) const {
    // A segment from inside whose end lies inside too crosses nothing (the
    // sphere is convex): most free flights are asked only this, in float,
    // with a margin far above float's rounding so that no crossing is missed.
    if (tmax < std::numeric_limits<float>::infinity()) {
        const float r2 = radius_ * radius_;
        const glm::vec3 from = o - centre_, to = from + tmax * d;
        if (glm::dot(from, from) < r2 * (1.f - kInsideMargin) && glm::dot(to, to) < r2 * (1.f - kInsideMargin))
            return std::nullopt;
    }
    const glm::dvec3 oc = glm::dvec3(o) - glm::dvec3(centre_);
    const glm::dvec3 dd(d);
    const double b = glm::dot(oc, dd);
    const glm::dvec3 q = oc - b * dd;
    const double r = double(radius_);
    const double h = r * r - glm::dot(q, q);
    if (!(h >= 0.0)) return std::nullopt;
    const double c = glm::dot(oc, oc) - r * r;
    const double far = -b + (b <= 0.0 ? std::sqrt(h) : -std::sqrt(h));  // the root of larger magnitude
    double t0 = far, t1 = far != 0.0 ? c / far : 0.0;
    if (t0 > t1) std::swap(t0, t1);
    double t;
    if (t0 > double(tmin) && t0 < double(tmax))
        t = t0;
    else if (t1 > double(tmin) && t1 < double(tmax))
        t = t1;
    else
        return std::nullopt;
    const glm::dvec3 n = (oc + t * dd) / r;
    RayHit hit;
    hit.t = float(t);
    hit.primitive = 0;
    encode_octahedral(glm::vec3(glm::normalize(n)), hit.u, hit.v);
    return hit;
}

SurfaceHit SphereBoundary::surface(const RayHit& ray_hit) const {
    SurfaceHit hit;
    hit.t = ray_hit.t;
    hit.primitive = 0;
    hit.u = ray_hit.u;
    hit.v = ray_hit.v;
    hit.geometric_normal = decode_octahedral(ray_hit.u, ray_hit.v);
    hit.shading_normal = hit.geometric_normal;
    return hit;
}

std::optional<SurfaceHit> SphereBoundary::intersect(const glm::vec3& o, const glm::vec3& d, float tmin,
                                                    float tmax) const {
    const std::optional<RayHit> hit = intersect_ray(o, d, tmin, tmax);
    if (!hit) return std::nullopt;
    return surface(*hit);
}

bool SphereBoundary::occluded(const glm::vec3& o, const glm::vec3& d, float tmin, float tmax) const {
    return intersect_ray(o, d, tmin, tmax).has_value();
}

void SphereBoundary::intersect_packet(const glm::vec3& origin, const glm::vec3* directions, int n,
                                      std::optional<SurfaceHit>* hits) const {
    if (n < 0 || n > kPacket) throw Error("internal: a ray packet holds at most 8 rays");
    for (int i = 0; i < n; ++i) hits[i] = intersect(origin, directions[i], 0.f, std::numeric_limits<float>::infinity());
}

std::optional<SurfaceHit> SphereBoundary::intersect_primitive(const glm::vec3& o, const glm::vec3& d,
                                                              std::uint32_t) const {
    return intersect(o, d, 0.f, std::numeric_limits<float>::infinity());
}

float SphereBoundary::distance_to_surface(const glm::vec3& p, float max_distance) const {
    const float d = std::abs(radius_ - glm::length(p - centre_));
    return std::min(d, max_distance);
}

// Tangents from the normal by Duff et al.'s branchless basis (2017).
SurfaceDifferential SphereBoundary::differential(const SurfaceHit& hit) const {
    const glm::vec3 n = hit.shading_normal;
    const float s = n.z < 0.f ? -1.f : 1.f;
    const float a = -1.f / (s + n.z), b = n.x * n.y * a;
    SurfaceDifferential sd;
    sd.tangent[0] = glm::vec3(1.f + s * n.x * n.x * a, s * b, -s * n.x);
    sd.tangent[1] = glm::vec3(b, s + n.y * n.y * a, -n.y);
    for (int k = 0; k < 2; ++k) sd.dn[k] = sd.tangent[k] / radius_;
    return sd;
}

}  // namespace jade
