#pragma once
// The object's boundary: a smooth dielectric interface (paper §5.3;
// docs/design.md, "Boundary").
//
//   split    the paper's model: reflect with weight `specular` (its specular
//            coefficient 0.5), refract with weight 1 − specular; where
//            refraction is impossible (total internal reflection) reflect with
//            weight 1. Energy is conserved, but the split ignores the angle.
//   fresnel  exact unpolarised Fresnel reflectance; the physical model and the
//            one other renderers (Mitsuba's `dielectric`) use.
//   none     index-matched: rays pass straight through; only the medium acts.
//
// Every mode is sampled exactly (the branch is chosen with the probability of
// its weight), so the sampled weight is 1. Radiance is not rescaled by η² on
// refraction: every light in a scene sits outside the object, so a path that
// reaches a light crosses the boundary in and out equally often and the
// factors cancel exactly.

#include "jade/geometry/boundary.h"

#include <glm/vec3.hpp>

#include <string>

namespace jade {

enum class BoundaryMode { Split, Fresnel, None };
const char* to_string(BoundaryMode mode);
BoundaryMode parse_boundary_mode(const std::string& name);  // throws jade::Error

// Unpolarised Fresnel reflectance for light arriving at cos_i > 0 to the
// normal on the side of index n_i, with eta = n_t / n_i. 1 under total
// internal reflection.
float fresnel_dielectric(float cos_i, float eta);

// Mirror direction of propagation direction d about unit normal n.
glm::vec3 reflect(const glm::vec3& d, const glm::vec3& n);

// Refraction of propagation direction d through the interface with unit
// normal n facing the incoming side (dot(d, n) < 0), eta = n_t / n_i.
// Returns false under total internal reflection.
bool refract(const glm::vec3& d, const glm::vec3& n, float eta, glm::vec3& out);

struct BoundaryParams {
    BoundaryMode mode = BoundaryMode::Split;
    float ior = 1.6f;        // interior index of refraction (the exterior is 1)
    float specular = 0.5f;   // split mode's reflection weight
    void validate() const;   // throws jade::Error
};

struct BoundarySample {
    glm::vec3 direction;  // new propagation direction
    bool reflected;       // true: the ray stays on its side
};

// The refracted branch alone, for estimators that follow it on purpose (next-
// event estimation through the boundary): its direction and its weight, the
// probability sample_boundary gives it (0 under total internal reflection).
struct BoundaryTransmission {
    glm::vec3 direction{0.f};
    float weight = 0.f;
};
BoundaryTransmission boundary_transmission(const BoundaryParams& params, const glm::vec3& d,
                                           const glm::vec3& n, bool entering);

// The normal of the interface a ray with propagation direction d meets at
// `hit`: the shading normal bends the interface smoothly; where it faces away
// from the ray's side of the triangle, the triangle's own normal is used.
glm::vec3 interface_normal(const SurfaceHit& hit, const glm::vec3& d, bool entering);

// Strict normals: whether propagation direction d_out lies on the side of
// the triangle (geometric normal ng) that the event put it on, arriving
// along d_in: a reflection goes back to d_in's side, a refraction crosses.
// A smooth shading normal can send a grazing ray the other way (a
// reflection out through the surface, a refraction back in); the interface
// makes no such path, so the integrator ends it, as the light estimators
// and the guide never follow one (docs/design.md, "Boundary"). Let through,
// those leaks reached the light by chains no estimator makes and were the
// demo's worst fireflies.
bool on_sampled_side(const glm::vec3& d_in, const glm::vec3& d_out, const glm::vec3& ng, bool reflected);

// Samples the interface for propagation direction d arriving at a surface
// with unit normal n (any orientation); `entering` says whether d comes from
// outside (index 1) into the object (index ior). u is uniform in [0, 1).
// Not for mode none, which has no interface.
BoundarySample sample_boundary(const BoundaryParams& params, const glm::vec3& d,
                               const glm::vec3& n, bool entering, float u);

}  // namespace jade
