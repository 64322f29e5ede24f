#pragma once
// The object's boundary as an analytic sphere (pbrt's and Mitsuba's
// `sphere` shape): every query is closed-form, the normals are exact, the
// distance to the surface is |r − |p − c||, and no acceleration structure
// is built. Reference scenes A and B are this sphere (data/reference/).

#include "jade/geometry/boundary.h"

#include <glm/vec3.hpp>

#include <vector>

namespace jade {

class SphereBoundary final : public Boundary {
public:
    // radius > 0 and finite, centre finite (else Error).
    SphereBoundary(const glm::vec3& centre, float radius);

    std::optional<SurfaceHit> intersect(const glm::vec3& origin, const glm::vec3& direction, float tmin,
                                        float tmax) const override;
    std::optional<RayHit> intersect_ray(const glm::vec3& origin, const glm::vec3& direction, float tmin,
                                        float tmax) const override;
    SurfaceHit surface(const RayHit& hit) const override;
    bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tmin, float tmax) const override;
    // One ray at a time: each costs a few multiplications.
    void intersect_packet(const glm::vec3& origin, const glm::vec3* directions, int n,
                          std::optional<SurfaceHit>* hits) const override;
    // The sphere is its one primitive: intersect(origin, direction, 0, ∞).
    std::optional<SurfaceHit> intersect_primitive(const glm::vec3& origin, const glm::vec3& direction,
                                                  std::uint32_t primitive) const override;
    // 0: a query is as cheap as the bound would be, so a free flight asks
    // for the surface at once rather than stepping toward it.
    float clearance(const glm::vec3&) const override { return 0.f; }
    float clearance_resolution() const override { return 0.f; }
    float distance_to_surface(const glm::vec3& p, float max_distance) const override;
    const Bounds3& bounds() const override { return bounds_; }
    // The bounding box's eight corners.
    const std::vector<glm::vec3>& hull_points() const override { return corners_; }
    bool convex() const override { return true; }
    // Any orthonormal tangents; the unit normal (p − c)/r turns by t/r along t.
    SurfaceDifferential differential(const SurfaceHit& hit) const override;

    const glm::vec3& centre() const { return centre_; }
    float radius() const { return radius_; }

private:
    glm::vec3 centre_;
    float radius_;
    Bounds3 bounds_;
    std::vector<glm::vec3> corners_;
};

}  // namespace jade
