#pragma once
// The object's boundary as a triangle mesh: an Embree 3 BVH over it. Owns
// its Embree device and scene (no global state); safe to query from many
// threads at once.

#include "jade/geometry/boundary.h"
#include "jade/geometry/clearance_grid.h"
#include "jade/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace jade {

class MeshAccel final : public Boundary {
public:
    // flat = true ignores vertex normals (shading normal = face normal).
    // detect_convex = false never reports the mesh convex (every query is
    // made: the reference the shortcut is tested against).
    explicit MeshAccel(const TriangleMesh& mesh, bool flat = false, bool detect_convex = true);
    ~MeshAccel();
    MeshAccel(const MeshAccel&) = delete;
    MeshAccel& operator=(const MeshAccel&) = delete;

    std::optional<SurfaceHit> intersect(const glm::vec3& origin, const glm::vec3& direction, float tmin,
                                        float tmax) const override;
    std::optional<RayHit> intersect_ray(const glm::vec3& origin, const glm::vec3& direction, float tmin,
                                        float tmax) const override;
    SurfaceHit surface(const RayHit& hit) const override;
    // Embree's occlusion query, which stops at the first triangle it finds
    // and fills in nothing.
    bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tmin, float tmax) const override;
    // Traced as one Embree packet (rtcIntersect8, flagged coherent): the
    // camera rays of one pixel run nearly parallel, and a packet of them
    // costs far less than its rays one by one.
    void intersect_packet(const glm::vec3& origin, const glm::vec3* directions, int n,
                          std::optional<SurfaceHit>* hits) const override;
    // Möller–Trumbore against the one triangle.
    std::optional<SurfaceHit> intersect_primitive(const glm::vec3& origin, const glm::vec3& direction,
                                                  std::uint32_t triangle) const override;
    // The clearance grid's bound (0 outside the mesh's box).
    float clearance(const glm::vec3& p) const override { return clearance_.at(p); }
    // One grid cell.
    float clearance_resolution() const override { return clearance_.cell_size(); }
    // An Embree closest-point query that visits only the triangles within
    // max_distance: for decisions the clearance grid is too coarse to make.
    float distance_to_surface(const glm::vec3& p, float max_distance) const override;
    const TriangleMesh& mesh() const { return mesh_; }
    // Kept: TriangleMesh::bounds() visits every vertex.
    const Bounds3& bounds() const override { return bounds_; }
    // The vertices.
    const std::vector<glm::vec3>& hull_points() const override { return mesh_.positions; }
    // geometry/topology.h, is_convex.
    bool convex() const override { return convex_; }
    SurfaceDifferential differential(const SurfaceHit& hit) const override;

private:
    struct Embree;
    const TriangleMesh& mesh_;
    Bounds3 bounds_;
    bool flat_;
    // What a hit needs of its triangle, in one 48-byte record: the unit face
    // normal, (p1 - p0) × (p2 - p0) normalised, and the three vertex normals.
    // Recomputing the face normal from the vertices cost as much as a tenth
    // of a render, and gathering it and the normals from four arrays missed
    // the cache four times a hit (11 % of scene B's time).
    struct TriangleShading {
        glm::vec3 face;
        glm::vec3 normal[3];
    };
    std::vector<TriangleShading> shading_;
    // What differential() needs of its triangle beyond that, in a second
    // record: two unit tangents of its plane (along p1 − p0, and the face
    // normal × it) and the unnormalised interpolated normal's derivative
    // along each (Σ n_i ∇b_i · tangent). The manifold walks ask for it at
    // every Newton step, and gathering it from the vertex arrays missed the
    // cache six times a call.
    struct TriangleFrame {
        glm::vec3 tangent[2];
        glm::vec3 dn[2];
    };
    static TriangleFrame triangle_frame(const TriangleMesh& mesh, std::size_t t, const glm::vec3& face, bool flat);
    std::vector<TriangleFrame> frames_;
    std::unique_ptr<Embree> embree_;
    ClearanceGrid clearance_;
    bool convex_ = false;
};

}  // namespace jade
