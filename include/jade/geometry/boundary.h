#pragma once
// The object's closed surface as the renderer asks about it: ray queries,
// the normals of a hit, how the surface bends around it, and bounds on the
// distance to it. Two shapes implement it: a triangle mesh traced by Embree
// (mesh_accel.h) and an analytic sphere (sphere_boundary.h), as pbrt's and
// Mitsuba's scenes offer both. Safe to query from many threads at once.

#include "jade/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace jade {

struct SurfaceHit {
    float t = 0.f;                 // distance along the (unit) ray direction
    std::uint32_t primitive = 0;   // the triangle's index (a sphere has one primitive, 0)
    float u = 0.f, v = 0.f;        // the surface's parameters there (RayHit)
    glm::vec3 geometric_normal{};  // unit, outward
    glm::vec3 shading_normal{};    // unit: interpolated vertex normals, or = geometric
};

// Where a ray meets the surface, before its normals are looked up
// (Boundary::surface): a free flight that scatters short of the surface
// needs only t, and a mesh's normals cost a cache miss a hit. u, v are a
// triangle's barycentrics of vertices 1 and 2, or the sphere's octahedral
// coordinates of its normal.
struct RayHit {
    float t = 0.f;
    std::uint32_t primitive = 0;
    float u = 0.f, v = 0.f;
};

// How the surface varies around a hit, for walks along it (manifold next-
// event estimation): two orthonormal tangents of the surface there and the
// derivatives of the unit shading normal along them (zero where the
// shading is flat).
struct SurfaceDifferential {
    glm::vec3 tangent[2]{};
    glm::vec3 dn[2]{};
};

class Boundary {
public:
    virtual ~Boundary() = default;

    // Closest hit with t in (tmin, tmax); direction must be unit length.
    virtual std::optional<SurfaceHit> intersect(const glm::vec3& origin, const glm::vec3& direction, float tmin,
                                                float tmax) const = 0;
    // The same query without the normals; surface() completes its hit.
    virtual std::optional<RayHit> intersect_ray(const glm::vec3& origin, const glm::vec3& direction, float tmin,
                                                float tmax) const = 0;
    virtual SurfaceHit surface(const RayHit& hit) const = 0;
    // Whether anything lies on the ray with t in (tmin, tmax) (shadow tests).
    virtual bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tmin, float tmax) const = 0;
    // The closest hits, t in (0, ∞), of n ≤ kPacket rays from one origin
    // (the camera rays of one pixel): hits[i] is what
    // intersect(origin, directions[i], 0, ∞) reports.
    static constexpr int kPacket = 8;
    virtual void intersect_packet(const glm::vec3& origin, const glm::vec3* directions, int n,
                                  std::optional<SurfaceHit>* hits) const = 0;
    // The hit, t > 0, of a ray with one given primitive alone, as intersect()
    // would report it: for walks along the surface that stay on a triangle,
    // without a BVH traversal. Nothing else is tested.
    virtual std::optional<SurfaceHit> intersect_primitive(const glm::vec3& origin, const glm::vec3& direction,
                                                          std::uint32_t primitive) const = 0;
    // At most the distance from p to the surface (0 where it is not known):
    // cheap enough to ask at every collision. A free flight shorter than it
    // cannot reach the surface (docs/design.md, "Clearance").
    virtual float clearance(const glm::vec3& p) const = 0;
    // Below this a clearance is not worth stepping by.
    virtual float clearance_resolution() const = 0;
    // The exact distance from p to the nearest point of the surface, or
    // `max_distance` when none lies closer. Costs about a ray query.
    virtual float distance_to_surface(const glm::vec3& p, float max_distance) const = 0;
    // The surface's bounding box.
    virtual const Bounds3& bounds() const = 0;
    // Points whose convex hull holds the whole surface (a mesh's vertices, a
    // sphere's bounding box): what a camera can see of it lies within their
    // projection.
    virtual const std::vector<glm::vec3>& hull_points() const = 0;
    // The surface bounds a convex body: a ray leaving it outward meets
    // nothing more, and needs no query.
    virtual bool convex() const = 0;
    // The shading normal's variation at `hit` (a hit this boundary returned).
    virtual SurfaceDifferential differential(const SurfaceHit& hit) const = 0;
};

}  // namespace jade
