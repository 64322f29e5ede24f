#pragma once
// Specular manifolds through the object's boundary (Hanika et al. 2015,
// "Manifold next event estimation"; docs/design.md, "Light estimators").
//
// One refraction: from a medium
// vertex p inside the object, the point y on the boundary where a straight
// ray from p refracts out into a given exterior direction ω. No ray query
// finds y: it is a root of a smooth function of the surface position,
// found by Newton's method on the surface (each step moves within the hit
// triangle's plane and is projected back onto the mesh by a ray from p, so
// the segment p → y never crosses the surface before y).
//
// The exterior direction ω_out(w) of an interior direction w is a smooth
// map; its Jacobian |dω_out/dw| (exterior solid angle per interior solid
// angle, curvature of the shading normals included) turns a density or a
// delta over exterior directions into one over the directions at p.

#include "jade/render/scene.h"

#include <glm/vec3.hpp>

#include <optional>

namespace jade {

struct PathCounters;

struct RefractedExit {
    SurfaceHit hit;             // where the ray from p meets the surface
    glm::vec3 direction{0.f};   // interior direction p → y (unit)
    glm::vec3 exterior{0.f};    // the refracted direction it leaves along
    float jacobian = 0.f;       // |dω_out/dw| at w = direction
    float transmission = 0.f;   // the boundary's weight of refracting out there
};

// The refraction out of the object of interior direction w (unit) from p,
// with its Jacobian; none when the ray does not leave by refraction through
// the smoothly shaded surface (total internal reflection, a shading normal
// that faces away, no surface). One ray query.
std::optional<RefractedExit> refracted_exit(const Scene& scene, const glm::vec3& p,
                                            const glm::vec3& w);

// The walk's seed: the target direction followed from p to where it meets
// the surface (the probe, one ray query), refracted inward there; exact on a
// flat surface. Also the primitive met (a triangle), where the seed's own ray most often
// lands too, and how far the probe went. None when the probe meets no
// surface facing the target.
struct RefractionSeed {
    glm::vec3 direction{0.f};
    std::uint32_t primitive = 0;
    float probe_distance = 0.f;
};
std::optional<RefractionSeed> refraction_seed(const Scene& scene, const glm::vec3& p, const glm::vec3& target);

// The interior direction from p that leaves along exterior direction
// `target` (unit): Newton's method from the seed above. The seed depends
// only on (p, target), so the result is a function of them (MIS needs to
// know which paths the solver finds). None when it does not converge to
// within kManifoldTolerance. The second form starts from a seed already
// made (refraction_seed(scene, p, target)).
std::optional<RefractedExit> solve_refracted_exit(const Scene& scene, const glm::vec3& p,
                                                  const glm::vec3& target, PathCounters& counters);
std::optional<RefractedExit> solve_refracted_exit(const Scene& scene, const glm::vec3& p,
                                                  const glm::vec3& target,
                                                  const std::optional<RefractionSeed>& seed,
                                                  PathCounters& counters);

// |ω_out − target| at which the solver stops (a chord length, ≈ radians).
constexpr float kManifoldTolerance = 2e-5f;

// Two vertices: the ray from p meets the surface at y1, reflects inside
// (the interface's internal reflection: total, or the split or Fresnel
// share), meets it again at y2 and refracts out. Light that scatters near a
// wall and leaves after one bounce off the inside of the surface (measured
// on the demo the largest share of the error the one-refraction walk left,
// docs/design.md, "Light estimators"). The unknown is y1 alone (y2 follows
// by tracing the reflected ray); the constraint is the refraction's at y2,
// as above, differentiated through the reflection by the chain rule.
struct ReflectedExit {
    SurfaceHit reflection;      // y1: where the ray from p meets the surface (t from p)
    SurfaceHit exit;            // y2: where the reflected ray meets it (t from y1)
    glm::vec3 direction{0.f};   // interior direction p → y1 (unit)
    glm::vec3 reflected{0.f};   // y1 → y2 (unit)
    glm::vec3 exterior{0.f};    // the refracted direction it leaves along
    float jacobian = 0.f;       // |dω_out/dw| at w = direction, through both vertices
    float weight = 0.f;         // the reflection's weight at y1 times the transmission at y2
    glm::vec3 reflection_point{0.f}, exit_point{0.f};  // y1, y2
};

// The chain of interior direction w from p: reflected at the first surface
// it meets, refracted out at the second; none when it does not go that way
// through the smoothly shaded surface (the reflection leaves the object, a
// shading normal faces away, total internal reflection at y2).
std::optional<ReflectedExit> reflected_exit(const Scene& scene, const glm::vec3& p,
                                            const glm::vec3& w);

// The interior direction from p whose two-vertex chain leaves along
// `target` (unit): Newton's method on y1, seeded deterministically from
// (p, target) by the mirror image of p in the wall the light, refracted in,
// travels toward (exact for flat surfaces); counted in the same counters as
// the one-refraction walk. None when it does not converge.
std::optional<ReflectedExit> solve_reflected_exit(const Scene& scene, const glm::vec3& p,
                                                  const glm::vec3& target, PathCounters& counters);

}  // namespace jade
