#pragma once
// Ray queries against the object's boundary: an Embree 3 BVH over one
// triangle mesh. Owns its Embree device and scene (no global state); safe to
// query from many threads at once.

#include "jade/geometry/clearance_grid.h"
#include "jade/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace jade {

struct SurfaceHit {
    float t = 0.f;                 // distance along the (unit) ray direction
    std::uint32_t triangle = 0;
    float u = 0.f, v = 0.f;        // barycentrics of vertices 1 and 2
    glm::vec3 geometric_normal{};  // unit, outward for outward winding
    glm::vec3 shading_normal{};    // unit, interpolated vertex normals (or = geometric)
};

// Where a ray meets the surface, before its triangle's normals are looked
// up (MeshAccel::surface): a free flight that scatters short of the surface
// needs only t, and the normals cost a cache miss a hit.
struct RayHit {
    float t = 0.f;
    std::uint32_t triangle = 0;
    float u = 0.f, v = 0.f;
};

// How the surface varies around a hit, for walks along it (manifold next-
// event estimation): two orthonormal tangents of the hit triangle's plane
// and the derivatives of the unit shading normal along them (zero where the
// shading is flat).
struct SurfaceDifferential {
    glm::vec3 tangent[2]{};
    glm::vec3 dn[2]{};
};

class MeshAccel {
public:
    // flat = true ignores vertex normals (shading normal = face normal).
    // detect_convex = false never reports the mesh convex (every query is
    // made: the reference the shortcut is tested against).
    explicit MeshAccel(const TriangleMesh& mesh, bool flat = false, bool detect_convex = true);
    ~MeshAccel();
    MeshAccel(const MeshAccel&) = delete;
    MeshAccel& operator=(const MeshAccel&) = delete;

    // Closest hit with t in (tmin, tmax); direction must be unit length.
    std::optional<SurfaceHit> intersect(const glm::vec3& origin, const glm::vec3& direction,
                                        float tmin, float tmax) const;
    // The same query without the normals; surface() completes its hit.
    std::optional<RayHit> intersect_ray(const glm::vec3& origin, const glm::vec3& direction,
                                        float tmin, float tmax) const;
    SurfaceHit surface(const RayHit& hit) const;
    // Whether anything lies on the ray with t in (tmin, tmax): Embree's
    // occlusion query, which stops at the first triangle it finds and
    // fills in nothing (shadow tests).
    bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tmin, float tmax) const;
    // The closest hits, t in (0, ∞), of n ≤ kPacket rays from one origin,
    // traced as one Embree packet (rtcIntersect8, flagged coherent): the
    // camera rays of one pixel run nearly parallel, and a packet of them
    // costs far less than its rays one by one. hits[i] is what
    // intersect(origin, directions[i], 0, ∞) reports.
    static constexpr int kPacket = 8;
    void intersect_packet(const glm::vec3& origin, const glm::vec3* directions, int n,
                          std::optional<SurfaceHit>* hits) const;
    // The hit of a ray with one given triangle alone (Möller–Trumbore, t > 0),
    // as intersect() would report it: for walks along the surface that stay
    // on a triangle, without a BVH traversal. Nothing else is tested.
    std::optional<SurfaceHit> intersect_triangle(const glm::vec3& origin, const glm::vec3& direction,
                                                 std::uint32_t triangle) const;
    // At most the distance from p to the surface (0 outside the mesh's box):
    // cheap enough to ask at every collision.
    float clearance(const glm::vec3& p) const { return clearance_.at(p); }
    // Below this a clearance is not worth stepping by (one grid cell).
    float clearance_resolution() const { return clearance_.cell_size(); }
    // The exact distance from p to the nearest point of the surface, or
    // `max_distance` when none lies closer (an Embree closest-point query
    // that visits only the triangles within max_distance). Costs about a ray
    // query: for decisions the clearance grid is too coarse to make.
    float distance_to_surface(const glm::vec3& p, float max_distance) const;
    const TriangleMesh& mesh() const { return mesh_; }
    // The mesh's bounding box (kept: TriangleMesh::bounds() visits every vertex).
    const Bounds3& bounds() const { return bounds_; }
    // The mesh bounds a convex body (geometry/topology.h, is_convex): a ray
    // leaving its surface outward needs no query, it meets nothing more.
    bool convex() const { return convex_; }
    // The shading normal's variation at `hit` (a hit this accelerator returned).
    SurfaceDifferential differential(const SurfaceHit& hit) const;

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
