#include "jade/render/specular_manifold.h"

#include "jade/core/sampling.h"
#include "jade/render/dielectric.h"
#include "jade/render/tracking.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace jade {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Newton proposals per solve (a step that does not lower the error is
// halved and counts as one). On the demo's vase a walk takes 4 on average.
constexpr int kMaxProposals = 24;
constexpr float kMinStep = 1.f / 1024.f;
// The exterior direction is checked once the constraint's sine is below this.
constexpr float kCheckExitBelow = 1e-3f;

// Refraction out through `hit`, reached from p along unit w, with the
// Jacobian |dω/dw|. With n the unit shading normal facing p (the inward one)
// and η = 1 / ior, the exit is ω = w/η + (c/η − c_t) n, c = −w·n,
// c_t = √(1 − (1 − c²)/η²); differentiated along a tangent step δy of y:
// δw = (δy − w (w·δy)) / r, δn from the mesh, δc = −(δw·n + w·δn),
// δc_t = c δc / (η² c_t).
std::optional<RefractedExit> exit_at(const Scene& scene, const glm::vec3& w, const SurfaceHit& hit) {
    const glm::vec3& ng = hit.geometric_normal;
    const glm::vec3& ns = hit.shading_normal;
    if (!(glm::dot(w, ng) > 0.f) || !(glm::dot(w, ns) > 0.f)) return std::nullopt;
    const BoundaryTransmission out = boundary_transmission(scene.interface, w, ns, false);
    if (!(out.weight > 0.f)) return std::nullopt;  // total internal reflection, or a mirror
    RefractedExit e;
    e.hit = hit;
    e.direction = w;
    e.exterior = out.direction;
    e.transmission = out.weight;

    const float eta = 1.f / scene.interface.ior;
    const glm::vec3 n = -ns;
    const float c = glm::dot(w, ns);
    const float ct = std::sqrt(std::max(0.f, 1.f - (1.f - c * c) / (eta * eta)));
    if (!(ct > 0.f)) return std::nullopt;  // grazing: the map is singular
    const SurfaceDifferential sd = scene.boundary->differential(hit);
    const float r = hit.t;
    glm::vec3 d_exterior[2];
    for (int k = 0; k < 2; ++k) {
        const glm::vec3 dw = (sd.tangent[k] - w * glm::dot(w, sd.tangent[k])) / r;
        const glm::vec3 dn = -sd.dn[k];
        const float dc = -(glm::dot(dw, n) + glm::dot(w, dn));
        const float dct = c * dc / (eta * eta * ct);
        d_exterior[k] = dw / eta + (dc / eta - dct) * n + (c / eta - ct) * dn;
    }
    // Solid angle: exterior per unit area of the triangle's plane, over the
    // interior solid angle per unit area, |w·n_g| / r².
    glm::vec3 b1, b2;
    orthonormal_basis(e.exterior, b1, b2);
    const float det_out = glm::dot(b1, d_exterior[0]) * glm::dot(b2, d_exterior[1]) -
                          glm::dot(b1, d_exterior[1]) * glm::dot(b2, d_exterior[0]);
    const float det_in = glm::dot(w, ng) / (r * r);
    e.jacobian = std::abs(det_out) / det_in;
    if (!(e.jacobian > 0.f) || !std::isfinite(e.jacobian)) return std::nullopt;
    return e;
}

// The seed: the target direction, followed backwards from where it meets
// the surface seen from p, refracted inward; exact on a flat surface.
std::optional<glm::vec3> seed_direction(const Scene& scene, const glm::vec3& p,
                                        const glm::vec3& target) {
    const auto probe = scene.boundary->intersect(p, target, 0.f, kInfinity);
    if (!probe || !(glm::dot(target, probe->geometric_normal) > 0.f)) return std::nullopt;
    const BoundaryTransmission in = boundary_transmission(
        scene.interface, -target, interface_normal(*probe, -target, true), true);
    if (in.direction == glm::vec3(0.f)) return std::nullopt;
    return -in.direction;
}

// A point of the walk: the surface hit from p along w, and the manifold
// constraint there (Hanika et al. 2015): with the generalised half vector
// H = η·ω_i + ω_o (ω_i = −w toward p, ω_o the target, η = ior), a
// refraction toward the target has H parallel to the shading normal n, so
// C = H × n vanishes. Unlike the refracted direction itself, C is smooth on
// both sides of the critical angle, where Newton's method on the exterior
// direction stalls. Its derivatives along the triangle's tangents are
// δC = (−η δw) × n + H × δn, expressed in a frame (b1, b2) of n.
struct WalkPoint {
    SurfaceHit hit;
    glm::vec3 w{0.f};
    float error = 0.f;  // |C| / |H|: the sine of the angle between H and n
    glm::vec3 tangent[2];
    float c[2];         // C in the frame
    float a[2][2];      // ∂c_j / ∂tangent_k
};

// The walk point along w from p. A step that stays on the previous point's
// triangle is intersected with that triangle alone (no BVH traversal; late
// Newton steps are small); the walk's end is checked against the whole mesh.
std::optional<WalkPoint> walk_point(const Scene& scene, const glm::vec3& p, const glm::vec3& w,
                                    const glm::vec3& target, const WalkPoint* previous = nullptr) {
    std::optional<SurfaceHit> hit;
    if (previous) hit = scene.boundary->intersect_triangle(p, w, previous->hit.triangle);
    if (!hit) hit = scene.boundary->intersect(p, w, 0.f, kInfinity);
    if (!hit || !(glm::dot(w, hit->geometric_normal) > 0.f)) return std::nullopt;
    WalkPoint wp;
    wp.hit = *hit;
    wp.w = w;
    const float eta = scene.interface.ior;
    const glm::vec3& n = hit->shading_normal;
    const glm::vec3 H = target - eta * w;
    const glm::vec3 C = glm::cross(H, n);
    wp.error = glm::length(C) / std::max(glm::length(H), 1e-12f);
    glm::vec3 b[2];
    orthonormal_basis(n, b[0], b[1]);
    const SurfaceDifferential sd = scene.boundary->differential(*hit);
    for (int k = 0; k < 2; ++k) {
        wp.tangent[k] = sd.tangent[k];
        const glm::vec3 dw = (sd.tangent[k] - w * glm::dot(w, sd.tangent[k])) / hit->t;
        const glm::vec3 dC = glm::cross(-eta * dw, n) + glm::cross(H, sd.dn[k]);
        for (int j = 0; j < 2; ++j) wp.a[j][k] = glm::dot(b[j], dC);
    }
    for (int j = 0; j < 2; ++j) wp.c[j] = glm::dot(b[j], C);
    return wp;
}

// The exit of a walk point whose constraint is small enough, if it leaves
// within the tolerance of the target and nothing lies between p and it.
std::optional<RefractedExit> converged(const Scene& scene, const glm::vec3& p, const WalkPoint& wp,
                                       const glm::vec3& target) {
    const auto e = exit_at(scene, wp.w, wp.hit);
    if (!e || !(glm::length(e->exterior - target) < kManifoldTolerance)) return std::nullopt;
    const auto first = scene.boundary->intersect(p, wp.w, 0.f, kInfinity);
    if (!first || first->triangle != wp.hit.triangle) return std::nullopt;
    return e;
}

}  // namespace

std::optional<RefractedExit> refracted_exit(const Scene& scene, const glm::vec3& p,
                                            const glm::vec3& w) {
    const auto hit = scene.boundary->intersect(p, w, 0.f, kInfinity);
    if (!hit) return std::nullopt;
    return exit_at(scene, w, *hit);
}

// Newton's method on the constraint, each step within the current hit's
// triangle plane and projected back onto the mesh by a ray from p; a step
// that does not lower the constraint is halved (Cycles' MNEE does the same).
std::optional<RefractedExit> solve_refracted_exit(const Scene& scene, const glm::vec3& p,
                                                  const glm::vec3& target, PathCounters& counters) {
    ++counters.manifold_walks;
    const auto seed = seed_direction(scene, p, target);
    std::optional<WalkPoint> cur = seed ? walk_point(scene, p, *seed, target) : std::nullopt;
    float step = 1.f;
    for (int proposal = 0; cur && proposal < kMaxProposals; ++proposal) {
        if (cur->error < kCheckExitBelow)
            if (const auto exit = converged(scene, p, *cur, target)) return exit;
        const float det = cur->a[0][0] * cur->a[1][1] - cur->a[0][1] * cur->a[1][0];
        if (!(std::abs(det) > 0.f)) break;
        const float x0 = -(cur->a[1][1] * cur->c[0] - cur->a[0][1] * cur->c[1]) / det;
        const float x1 = -(cur->a[0][0] * cur->c[1] - cur->a[1][0] * cur->c[0]) / det;
        const glm::vec3 y = p + cur->hit.t * cur->w;
        const glm::vec3 to = y + step * (x0 * cur->tangent[0] + x1 * cur->tangent[1]) - p;
        const float len = glm::length(to);
        std::optional<WalkPoint> next =
            len > 0.f ? walk_point(scene, p, to / len, target, &*cur) : std::nullopt;
        if (next && next->error < cur->error) {
            cur = next;
            step = std::min(1.f, 2.f * step);
        } else if ((step *= 0.5f) < kMinStep) {
            break;
        }
    }
    if (cur)
        if (const auto exit = converged(scene, p, *cur, target)) return exit;
    ++counters.manifold_failures;
    return std::nullopt;
}

}  // namespace jade
