#pragma once
// The one-refraction specular manifold (Hanika et al. 2015, "Manifold next
// event estimation"; docs/design.md, "Light estimators"): from a medium
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

// The interior direction from p that leaves along exterior direction
// `target` (unit): Newton's method from the ray that the target direction,
// refracted inward where it meets the surface from p, would take. The seed
// depends only on (p, target), so the result is a function of them (MIS
// needs to know which paths the solver finds). None when it does not
// converge to within kManifoldTolerance.
std::optional<RefractedExit> solve_refracted_exit(const Scene& scene, const glm::vec3& p,
                                                  const glm::vec3& target, PathCounters& counters);

// |ω_out − target| at which the solver stops (a chord length, ≈ radians).
constexpr float kManifoldTolerance = 2e-5f;

}  // namespace jade
