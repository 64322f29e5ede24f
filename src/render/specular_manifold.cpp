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
// A constraint this small at a point that is not an exit: a root of the
// wrong kind (newton_walk).
constexpr float kSpuriousBelow = 1e-5f;
// A hit this close to the walk's exit, relative to its distance, is the
// exit's own surface (a neighbouring triangle across an edge).
constexpr float kSameSurface = 1e-4f;

// The refraction out of interior direction w through outward unit shading
// normal ns (w·ns = c > 0): with n = −ns facing the inside and η = 1 / ior,
// ω = w/η + (c/η − c_t) n, c_t = √(1 − (1 − c²)/η²). Differentiated for a
// change δw of the direction and δns of the normal: δn = −δns,
// δc = −(δw·n + w·δn), δc_t = c δc / (η² c_t).
struct OutwardRefraction {
    float eta, c, ct;
    glm::vec3 w, n;
    glm::vec3 derivative(const glm::vec3& dw, const glm::vec3& dns) const {
        const glm::vec3 dn = -dns;
        const float dc = -(glm::dot(dw, n) + glm::dot(w, dn));
        const float dct = c * dc / (eta * eta * ct);
        return dw / eta + (dc / eta - dct) * n + (c / eta - ct) * dn;
    }
};

std::optional<OutwardRefraction> outward_refraction(const Scene& scene, const glm::vec3& w, const glm::vec3& ns) {
    OutwardRefraction r{1.f / scene.interface.ior, glm::dot(w, ns), 0.f, w, -ns};
    r.ct = std::sqrt(std::max(0.f, 1.f - (1.f - r.c * r.c) / (r.eta * r.eta)));
    if (!(r.ct > 0.f)) return std::nullopt;  // grazing: the map is singular
    return r;
}

// Solid angle: the exterior directions' spanned by their derivatives along
// two orthonormal tangents of a triangle's plane, over the interior solid
// angle per unit area of that plane, |w·n_g| / r².
float solid_angle_ratio(const glm::vec3& exterior, const glm::vec3 (&d_exterior)[2], float w_dot_ng, float r) {
    glm::vec3 b1, b2;
    orthonormal_basis(exterior, b1, b2);
    const float det_out = glm::dot(b1, d_exterior[0]) * glm::dot(b2, d_exterior[1]) -
                          glm::dot(b1, d_exterior[1]) * glm::dot(b2, d_exterior[0]);
    return std::abs(det_out) / (w_dot_ng / (r * r));
}

// Refraction out through `hit`, reached from p along unit w, with the
// Jacobian |dω/dw|: along a tangent step δy of y, δw = (δy − w (w·δy)) / r.
std::optional<RefractedExit> exit_at(const Scene& scene, const glm::vec3& w, const SurfaceHit& hit) {
    const glm::vec3& ng = hit.geometric_normal;
    const glm::vec3& ns = hit.shading_normal;
    if (!(glm::dot(w, ng) > 0.f) || !(glm::dot(w, ns) > 0.f)) return std::nullopt;
    const BoundaryTransmission out = boundary_transmission(scene.interface, w, ns, false);
    if (!(out.weight > 0.f)) return std::nullopt;  // total internal reflection, or a mirror
    if (!on_sampled_side(w, out.direction, ng, false)) return std::nullopt;  // a leak back in
    const auto refraction = outward_refraction(scene, w, ns);
    if (!refraction) return std::nullopt;
    RefractedExit e;
    e.hit = hit;
    e.direction = w;
    e.exterior = out.direction;
    e.transmission = out.weight;
    const SurfaceDifferential sd = scene.boundary->differential(hit);
    const float r = hit.t;
    glm::vec3 d_exterior[2];
    for (int k = 0; k < 2; ++k)
        d_exterior[k] = refraction->derivative((sd.tangent[k] - w * glm::dot(w, sd.tangent[k])) / r, sd.dn[k]);
    e.jacobian = solid_angle_ratio(e.exterior, d_exterior, glm::dot(w, ng), r);
    if (!(e.jacobian > 0.f) || !std::isfinite(e.jacobian)) return std::nullopt;
    return e;
}

// A point of the walk: the surface hit from p along w, and the manifold
// constraint there (Hanika et al. 2015): with the generalised half vector
// H = η·ω_i + ω_o (ω_i = −w toward p, ω_o the target, η = ior), a
// refraction toward the target has H parallel to the shading normal n, so
// C = H × n vanishes. Unlike the refracted direction itself, C is smooth on
// both sides of the critical angle, where Newton's method on the exterior
// direction stalls. Its derivatives along the triangle's tangents are
// δC = (−η δw) × n + H × δn, expressed in a frame (b1, b2) of n.
// A point is made in two parts: its constraint's size first, which decides
// whether a Newton step is kept, then (newton_walk's `complete`) the
// derivatives the next step needs, only for the points kept.
struct WalkPoint {
    SurfaceHit hit;
    glm::vec3 y{0.f};   // the point the walk moves: where the ray from p meets the surface
    glm::vec3 w{0.f};
    glm::vec3 H{0.f}, C{0.f};
    float error = 0.f;  // |C| / |H|: the sine of the angle between H and n
    glm::vec3 tangent[2];
    float c[2];         // C in the frame
    float a[2][2];      // ∂c_j / ∂tangent_k
};

// The walk point along w from p, up to its derivatives. A step that stays
// on the previous point's triangle is intersected with that triangle alone
// (no BVH traversal; late Newton steps are small); the walk's end is
// checked against the whole mesh.
std::optional<WalkPoint> walk_point(const Scene& scene, const glm::vec3& p, const glm::vec3& w,
                                    const glm::vec3& target, const WalkPoint* previous = nullptr) {
    std::optional<SurfaceHit> hit;
    if (previous) hit = scene.boundary->intersect_primitive(p, w, previous->hit.primitive);
    if (!hit) hit = scene.boundary->intersect(p, w, 0.f, kInfinity);
    if (!hit || !(glm::dot(w, hit->geometric_normal) > 0.f)) return std::nullopt;
    WalkPoint wp;
    wp.hit = *hit;
    wp.y = p + hit->t * w;
    wp.w = w;
    wp.H = target - scene.interface.ior * w;
    wp.C = glm::cross(wp.H, hit->shading_normal);
    wp.error = glm::length(wp.C) / std::max(glm::length(wp.H), 1e-12f);
    return wp;
}

// The constraint's derivatives at a walk point.
void walk_derivatives(const Scene& scene, WalkPoint& wp) {
    const float eta = scene.interface.ior;
    const glm::vec3& n = wp.hit.shading_normal;
    glm::vec3 b[2];
    orthonormal_basis(n, b[0], b[1]);
    const SurfaceDifferential sd = scene.boundary->differential(wp.hit);
    for (int k = 0; k < 2; ++k) {
        wp.tangent[k] = sd.tangent[k];
        const glm::vec3 dw = (sd.tangent[k] - wp.w * glm::dot(wp.w, sd.tangent[k])) / wp.hit.t;
        const glm::vec3 dC = glm::cross(-eta * dw, n) + glm::cross(wp.H, sd.dn[k]);
        for (int j = 0; j < 2; ++j) wp.a[j][k] = glm::dot(b[j], dC);
    }
    for (int j = 0; j < 2; ++j) wp.c[j] = glm::dot(b[j], wp.C);
}

// The exit of a walk point whose constraint is small enough, if it leaves
// within the tolerance of the target and nothing lies between p and it.
std::optional<RefractedExit> converged(const Scene& scene, const glm::vec3& p, const WalkPoint& wp,
                                       const glm::vec3& target) {
    const auto e = exit_at(scene, wp.w, wp.hit);
    if (!e || !(glm::length(e->exterior - target) < kManifoldTolerance)) return std::nullopt;
    // Nothing on the segment before the exit (the walk's steps were tested
    // against their own triangles only).
    if (scene.boundary->occluded(p, wp.w, 0.f, wp.hit.t * (1.f - kSameSurface))) return std::nullopt;
    return e;
}

// Newton's method on a walk's two constraint coordinates (Hanika et al.
// 2015): each step moves the walk's point y within its triangle's plane and
// is projected back onto the mesh by a ray from p (so the segment p → y never
// crosses the surface before y); a step that does not lower the constraint
// is halved (Cycles' MNEE does the same). `at(w, previous)` is the walk point
// along interior direction w up to its derivatives, `complete(point)` adds
// them (only to the points a step keeps: most proposals of a walk that
// stalls are not kept), and `converged(point)` is its exit, if it is one
// (asked once a point: it is a function of the point).
// With `stop_at_wrong_roots`, a constraint that has vanished at a point that
// is not an exit ends the walk: a root of the wrong kind (the half vector
// antiparallel to the refraction's, the target on the inner side), from
// which no step leads on. The two-vertex walk meets many (a quarter of its
// failures on the demo, each spending all its proposals); the one-refraction
// walk rarely, and there the steps that go on still find 5 of 338 sphere
// solutions.
template <class Point, class At, class Complete, class Converged>
auto newton_walk(const glm::vec3& p, std::optional<Point> cur, At at, Complete complete, Converged converged,
                 bool stop_at_wrong_roots) -> decltype(converged(*cur)) {
    if (cur) complete(*cur);
    float step = 1.f;
    bool asked = false;  // converged(*cur) was asked, and was none
    for (int proposal = 0; cur && proposal < kMaxProposals; ++proposal) {
        if (!asked && cur->error < kCheckExitBelow) {
            if (auto exit = converged(*cur)) return exit;
            if (stop_at_wrong_roots && cur->error < kSpuriousBelow) return std::nullopt;
            asked = true;
        }
        const float det = cur->a[0][0] * cur->a[1][1] - cur->a[0][1] * cur->a[1][0];
        if (!(std::abs(det) > 0.f)) break;
        const float x0 = -(cur->a[1][1] * cur->c[0] - cur->a[0][1] * cur->c[1]) / det;
        const float x1 = -(cur->a[0][0] * cur->c[1] - cur->a[1][0] * cur->c[0]) / det;
        const glm::vec3 to = cur->y + step * (x0 * cur->tangent[0] + x1 * cur->tangent[1]) - p;
        const float len = glm::length(to);
        std::optional<Point> next = len > 0.f ? at(to / len, *cur) : std::nullopt;
        if (next && next->error < cur->error) {
            complete(*next);
            cur = next;
            asked = false;
            step = std::min(1.f, 2.f * step);
        } else if ((step *= 0.5f) < kMinStep) {
            break;
        }
    }
    if (cur && !asked) return converged(*cur);
    return std::nullopt;
}

}  // namespace

std::optional<RefractedExit> refracted_exit(const Scene& scene, const glm::vec3& p,
                                            const glm::vec3& w) {
    const auto hit = scene.boundary->intersect(p, w, 0.f, kInfinity);
    if (!hit) return std::nullopt;
    return exit_at(scene, w, *hit);
}

std::optional<RefractionSeed> refraction_seed(const Scene& scene, const glm::vec3& p, const glm::vec3& target) {
    const auto probe = scene.boundary->intersect(p, target, 0.f, kInfinity);
    if (!probe || !(glm::dot(target, probe->geometric_normal) > 0.f)) return std::nullopt;
    const BoundaryTransmission in = boundary_transmission(
        scene.interface, -target, interface_normal(*probe, -target, true), true);
    if (in.direction == glm::vec3(0.f)) return std::nullopt;
    return RefractionSeed{-in.direction, probe->primitive, probe->t};
}

std::optional<RefractedExit> solve_refracted_exit(const Scene& scene, const glm::vec3& p,
                                                  const glm::vec3& target, PathCounters& counters) {
    return solve_refracted_exit(scene, p, target, refraction_seed(scene, p, target), counters);
}

std::optional<RefractedExit> solve_refracted_exit(const Scene& scene, const glm::vec3& p,
                                                  const glm::vec3& target,
                                                  const std::optional<RefractionSeed>& seed,
                                                  PathCounters& counters) {
    ++counters.manifold_walks;
    std::optional<WalkPoint> start;
    if (seed) {
        WalkPoint probed;
        probed.hit.primitive = seed->primitive;
        start = walk_point(scene, p, seed->direction, target, &probed);
    }
    const auto exit = newton_walk(
        p, start,
        [&](const glm::vec3& w, const WalkPoint& previous) { return walk_point(scene, p, w, target, &previous); },
        [&](WalkPoint& point) { walk_derivatives(scene, point); },
        [&](const WalkPoint& point) { return converged(scene, p, point, target); }, false);
    if (!exit) ++counters.manifold_failures;
    return exit;
}

// ---------------------------------------------------------------------------
// Two vertices: an internal reflection at y1, then the refraction out at y2.

namespace {

// A point of the two-vertex walk: the chain traced from p along w, the
// refraction constraint at y2 (as WalkPoint's) and its derivatives along y1's
// triangle tangents, and what the Jacobian needs: δd and δn_s at y2 per
// tangent. Along a tangent step δy1 (r1 = |y1 − p|, n1 the shading normal):
//   δw  = (δy1 − w (w·δy1)) / r1
//   δd  = δw − 2 [(δw·n1 + w·δn1) n1 + (w·n1) δn1]     (d = w − 2 (w·n1) n1)
//   δy2 = v − d (v·n_g2) / (d·n_g2),  v = δy1 + r2 δd   (y2 stays on its plane)
//   δn2 from δy2's components along y2's tangents.
struct ChainPoint {
    SurfaceHit first, second;  // y1 (t from p) and y2 (t from y1's spawn point)
    glm::vec3 y{0.f}, y2{0.f};  // y1, the point the walk moves, and y2
    glm::vec3 w{0.f}, d{0.f};
    glm::vec3 H{0.f}, C{0.f};
    float error = 0.f;
    glm::vec3 tangent[2];
    float c[2];
    float a[2][2];
    glm::vec3 dd[2], dn2[2];
};

// The chain's first vertex along w from p, and the reflected ray's hit.
// Steps that stay on the previous point's triangles are intersected with
// those alone (late Newton steps are small); converged chains are checked
// against the whole mesh.
bool trace_chain(const Scene& scene, const glm::vec3& p, const glm::vec3& w, ChainPoint& cp,
                 const ChainPoint* previous) {
    std::optional<SurfaceHit> first;
    if (previous) first = scene.boundary->intersect_primitive(p, w, previous->first.primitive);
    if (!first) first = scene.boundary->intersect(p, w, 0.f, kInfinity);
    if (!first || !(glm::dot(w, first->geometric_normal) > 0.f) || !(glm::dot(w, first->shading_normal) > 0.f))
        return false;
    const glm::vec3 d = reflect(w, first->shading_normal);
    if (!on_sampled_side(w, d, first->geometric_normal, true)) return false;  // the reflection would leave
    const glm::vec3 y1 = p + first->t * w;
    const Scene::Spawn spawn = scene.spawn_inside(y1, first->geometric_normal, d);
    std::optional<SurfaceHit> second;
    if (previous) second = scene.boundary->intersect_primitive(spawn.origin, d, previous->second.primitive);
    if (!second) second = scene.boundary->intersect(spawn.origin, d, spawn.query_from, kInfinity);
    if (!second || !(glm::dot(d, second->geometric_normal) > 0.f) || !(glm::dot(d, second->shading_normal) > 0.f))
        return false;
    cp.first = *first;
    cp.second = *second;
    cp.y = y1;
    cp.y2 = spawn.origin + second->t * d;
    cp.w = w;
    cp.d = d;
    return true;
}

void chain_derivatives(const Scene& scene, ChainPoint& cp) {
    const glm::vec3& n1 = cp.first.shading_normal;
    const glm::vec3& ng2 = cp.second.geometric_normal;
    const SurfaceDifferential s1 = scene.boundary->differential(cp.first);
    const SurfaceDifferential s2 = scene.boundary->differential(cp.second);
    const float r1 = cp.first.t, r2 = cp.second.t;
    const float wn = glm::dot(cp.w, n1);
    for (int k = 0; k < 2; ++k) {
        const glm::vec3& dy1 = s1.tangent[k];
        cp.tangent[k] = dy1;
        const glm::vec3 dw = (dy1 - cp.w * glm::dot(cp.w, dy1)) / r1;
        const glm::vec3& dn1 = s1.dn[k];
        cp.dd[k] = dw - 2.f * ((glm::dot(dw, n1) + glm::dot(cp.w, dn1)) * n1 + wn * dn1);
        const glm::vec3 v = dy1 + r2 * cp.dd[k];
        const glm::vec3 dy2 = v - cp.d * (glm::dot(v, ng2) / glm::dot(cp.d, ng2));
        cp.dn2[k] = s2.dn[0] * glm::dot(dy2, s2.tangent[0]) + s2.dn[1] * glm::dot(dy2, s2.tangent[1]);
    }
}

// The refraction constraint at y2 toward `target` (WalkPoint's).
void chain_constraint(const Scene& scene, const glm::vec3& target, ChainPoint& cp) {
    cp.H = target - scene.interface.ior * cp.d;
    cp.C = glm::cross(cp.H, cp.second.shading_normal);
    cp.error = glm::length(cp.C) / std::max(glm::length(cp.H), 1e-12f);
}

// Its derivatives along y1's tangents: δC = (−η δd) × n2 + H × δn2.
void chain_constraint_derivatives(const Scene& scene, ChainPoint& cp) {
    chain_derivatives(scene, cp);
    const float eta = scene.interface.ior;
    const glm::vec3& n2 = cp.second.shading_normal;
    glm::vec3 b[2];
    orthonormal_basis(n2, b[0], b[1]);
    for (int k = 0; k < 2; ++k) {
        const glm::vec3 dC = glm::cross(-eta * cp.dd[k], n2) + glm::cross(cp.H, cp.dn2[k]);
        for (int j = 0; j < 2; ++j) cp.a[j][k] = glm::dot(b[j], dC);
    }
    for (int j = 0; j < 2; ++j) cp.c[j] = glm::dot(b[j], cp.C);
}

// The chain along w from p up to its derivatives (newton_walk's `at`).
std::optional<ChainPoint> chain_point(const Scene& scene, const glm::vec3& p, const glm::vec3& w,
                                      const glm::vec3& target, const ChainPoint* previous = nullptr) {
    ChainPoint cp;
    if (!trace_chain(scene, p, w, cp, previous)) return std::nullopt;
    chain_constraint(scene, target, cp);
    return cp;
}

// The exit of a traced chain: the weights of both events and |dω/dw| (the
// exterior direction's derivative through δd and δn2, over the interior
// solid angle per unit area of y1's plane).
std::optional<ReflectedExit> chain_exit(const Scene& scene, const ChainPoint& cp) {
    const glm::vec3& ns2 = cp.second.shading_normal;
    const BoundaryTransmission out = boundary_transmission(scene.interface, cp.d, ns2, false);
    if (!(out.weight > 0.f) || !on_sampled_side(cp.d, out.direction, cp.second.geometric_normal, false))
        return std::nullopt;
    const float reflectance = 1.f - boundary_transmission(scene.interface, cp.w, cp.first.shading_normal, false).weight;
    const auto refraction = outward_refraction(scene, cp.d, ns2);
    if (!refraction || !(reflectance > 0.f)) return std::nullopt;
    ReflectedExit e;
    e.reflection = cp.first;
    e.exit = cp.second;
    e.direction = cp.w;
    e.reflected = cp.d;
    e.exterior = out.direction;
    e.weight = reflectance * out.weight;
    e.reflection_point = cp.y;
    e.exit_point = cp.y2;
    glm::vec3 d_exterior[2];
    for (int k = 0; k < 2; ++k) d_exterior[k] = refraction->derivative(cp.dd[k], cp.dn2[k]);
    e.jacobian = solid_angle_ratio(e.exterior, d_exterior, glm::dot(cp.w, cp.first.geometric_normal), cp.first.t);
    if (!(e.jacobian > 0.f) || !std::isfinite(e.jacobian)) return std::nullopt;
    return e;
}

// The seed: the target direction refracted inward where it meets the
// surface seen from p gives the light's direction d_in inside; the wall it
// travels toward from p (hit along d_in, tangent plane at q, outward normal
// n) reflects it back to p from y1 = p' − s d_in, p' = p − 2 ((p − q)·n) n
// the mirror image of p and s where that line meets the plane. Exact for
// flat surfaces.
std::optional<glm::vec3> reflected_seed(const Scene& scene, const glm::vec3& p, const glm::vec3& target) {
    const auto in = refraction_seed(scene, p, target);
    if (!in) return std::nullopt;
    const glm::vec3 d_in = -in->direction;
    const auto wall = scene.boundary->intersect(p, d_in, 0.f, kInfinity);
    if (!wall) return std::nullopt;
    const glm::vec3& n = wall->geometric_normal;
    const float toward = glm::dot(d_in, n);
    if (!(toward > 0.f)) return std::nullopt;
    const glm::vec3 q = p + wall->t * d_in;
    const glm::vec3 image = p - 2.f * glm::dot(p - q, n) * n;
    const glm::vec3 y1 = image - (glm::dot(image - q, n) / toward) * d_in;
    const glm::vec3 to = y1 - p;
    const float len = glm::length(to);
    if (!(len > 0.f)) return std::nullopt;
    return to / len;
}

// A converged chain's exit, if it leaves within the tolerance of the target
// and its legs meet no other surface first.
std::optional<ReflectedExit> chain_converged(const Scene& scene, const glm::vec3& p, const ChainPoint& cp,
                                             const glm::vec3& target) {
    const auto e = chain_exit(scene, cp);
    if (!e || !(glm::length(e->exterior - target) < kManifoldTolerance)) return std::nullopt;
    ChainPoint whole;
    if (!trace_chain(scene, p, cp.w, whole, nullptr) || whole.first.primitive != cp.first.primitive ||
        whole.second.primitive != cp.second.primitive)
        return std::nullopt;
    return e;
}

}  // namespace

std::optional<ReflectedExit> reflected_exit(const Scene& scene, const glm::vec3& p, const glm::vec3& w) {
    ChainPoint cp;
    if (!trace_chain(scene, p, w, cp, nullptr)) return std::nullopt;
    chain_derivatives(scene, cp);
    return chain_exit(scene, cp);
}

// Newton's method on y1 (newton_walk), the chain traced on from each step.
std::optional<ReflectedExit> solve_reflected_exit(const Scene& scene, const glm::vec3& p,
                                                  const glm::vec3& target, PathCounters& counters) {
    ++counters.manifold_walks;
    const auto seed = reflected_seed(scene, p, target);
    const auto exit = newton_walk(
        p, seed ? chain_point(scene, p, *seed, target) : std::nullopt,
        [&](const glm::vec3& w, const ChainPoint& previous) { return chain_point(scene, p, w, target, &previous); },
        [&](ChainPoint& point) { chain_constraint_derivatives(scene, point); },
        [&](const ChainPoint& point) { return chain_converged(scene, p, point, target); }, true);
    if (!exit) ++counters.manifold_failures;
    return exit;
}

}  // namespace jade
