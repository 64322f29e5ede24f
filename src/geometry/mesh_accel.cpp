#include "jade/geometry/mesh_accel.h"

#include "jade/core/error.h"
#include "jade/geometry/topology.h"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace jade {

namespace {
// Cells of the clearance grid along the mesh's longest side: a cell is
// 1/128 of the object, a few percent of a typical mean free path; the grid
// costs 8 MB at most and about 0.1 s to build.
constexpr int kClearanceCells = 128;
}  // namespace

struct MeshAccel::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Embree() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

// The shading normal is the normalised ñ = Σ b_i n_i over the barycentrics
// b_i, which are linear in the position y on the triangle's plane: with
// e1 = p1 − p0, e2 = p2 − p0 and N = e1 × e2, ∇b_1 = (e2 × N) / |N|² and
// ∇b_2 = (N × e1) / |N|², so ñ changes along a tangent t by
// (n1 − n0)(∇b_1·t) + (n2 − n0)(∇b_2·t). A degenerate triangle has no frame
// (zero tangents), a flat-shaded one no change of the normal.
MeshAccel::TriangleFrame MeshAccel::triangle_frame(const TriangleMesh& mesh, std::size_t t, const glm::vec3& face,
                                                   bool flat) {
    TriangleFrame f{};
    const auto& tri = mesh.triangles[t];
    const glm::vec3 e1 = mesh.positions[tri[1]] - mesh.positions[tri[0]];
    const glm::vec3 e2 = mesh.positions[tri[2]] - mesh.positions[tri[0]];
    const float e1_len = glm::length(e1);
    if (!(e1_len > 0.f)) return f;
    f.tangent[0] = e1 / e1_len;
    f.tangent[1] = glm::cross(face, f.tangent[0]);
    if (flat) return f;
    const glm::vec3 N = glm::cross(e1, e2);
    const float N2 = glm::dot(N, N);
    const glm::vec3 grad_u = glm::cross(e2, N) / N2, grad_v = glm::cross(N, e1) / N2;
    const glm::vec3& n0 = mesh.normals[tri[0]];
    for (int k = 0; k < 2; ++k)
        f.dn[k] = (mesh.normals[tri[1]] - n0) * glm::dot(grad_u, f.tangent[k]) +
                  (mesh.normals[tri[2]] - n0) * glm::dot(grad_v, f.tangent[k]);
    return f;
}

MeshAccel::MeshAccel(const TriangleMesh& mesh, bool flat, bool detect_convex)
    : mesh_(mesh), bounds_(mesh.bounds()), flat_(flat), embree_(std::make_unique<Embree>()),
      clearance_(mesh, kClearanceCells), convex_(detect_convex && is_convex(mesh)) {
    shading_.reserve(mesh.triangles.size());
    frames_.reserve(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::vec3 n = mesh.face_normal(t);
        const float len = glm::length(n);
        TriangleShading ts;
        ts.face = len > 0.f ? n / len : glm::vec3(0.f);
        for (int k = 0; k < 3; ++k)
            ts.normal[k] = flat ? ts.face : mesh.normals[mesh.triangles[t][std::size_t(k)]];
        shading_.push_back(ts);
        frames_.push_back(triangle_frame(mesh, t, ts.face, flat));
    }
    embree_->device = rtcNewDevice(nullptr);
    if (!embree_->device) throw Error("cannot start Embree (rtcNewDevice failed)");
    embree_->scene = rtcNewScene(embree_->device);
    // Robust traversal: no rays slip between triangles sharing an edge, which
    // would let light leak through a closed boundary.
    rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), mesh.triangles.size()));
    if (!vb || !ib) throw Error("Embree could not allocate the mesh buffers");
    std::memcpy(vb, mesh.positions.data(), mesh.positions.size() * 3 * sizeof(float));
    std::memcpy(ib, mesh.triangles.data(), mesh.triangles.size() * 3 * sizeof(std::uint32_t));
    rtcCommitGeometry(geom);
    rtcAttachGeometry(embree_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(embree_->scene);
    if (rtcGetDeviceError(embree_->device) != RTC_ERROR_NONE)
        throw Error("Embree failed to build the BVH for " + mesh.path);
}

MeshAccel::~MeshAccel() = default;

std::optional<SurfaceHit> MeshAccel::intersect(const glm::vec3& o, const glm::vec3& d, float tmin,
                                               float tmax) const {
    const std::optional<RayHit> hit = intersect_ray(o, d, tmin, tmax);
    if (!hit) return std::nullopt;
    return surface(*hit);
}

namespace {
// One ray for Embree's single-ray queries.
RTCRay embree_ray(const glm::vec3& o, const glm::vec3& d, float tmin, float tmax) {
    RTCRay ray;
    ray.org_x = o.x;
    ray.org_y = o.y;
    ray.org_z = o.z;
    ray.dir_x = d.x;
    ray.dir_y = d.y;
    ray.dir_z = d.z;
    ray.tnear = tmin;
    ray.tfar = tmax;
    ray.time = 0.f;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
    return ray;
}
}  // namespace

std::optional<RayHit> MeshAccel::intersect_ray(const glm::vec3& o, const glm::vec3& d, float tmin,
                                               float tmax) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray = embree_ray(o, d, tmin, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return RayHit{rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v};
}

bool MeshAccel::occluded(const glm::vec3& o, const glm::vec3& d, float tmin, float tmax) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray = embree_ray(o, d, tmin, tmax);
    rtcOccluded1(embree_->scene, &context, &ray);
    return ray.tfar < 0.f;  // Embree sets tfar to −∞ on a hit
}

void MeshAccel::intersect_packet(const glm::vec3& origin, const glm::vec3* directions, int n,
                                 std::optional<SurfaceHit>* hits) const {
    if (n < 0 || n > kPacket) throw Error("internal: a ray packet holds at most 8 rays");
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) int valid[kPacket];
    alignas(32) RTCRayHit8 rh;
    for (int i = 0; i < kPacket; ++i) {
        valid[i] = i < n ? -1 : 0;
        const glm::vec3 d = i < n ? directions[i] : glm::vec3(0.f, 0.f, 1.f);
        rh.ray.org_x[i] = origin.x;
        rh.ray.org_y[i] = origin.y;
        rh.ray.org_z[i] = origin.z;
        rh.ray.dir_x[i] = d.x;
        rh.ray.dir_y[i] = d.y;
        rh.ray.dir_z[i] = d.z;
        rh.ray.tnear[i] = 0.f;
        rh.ray.tfar[i] = std::numeric_limits<float>::infinity();
        rh.ray.time[i] = 0.f;
        rh.ray.mask[i] = 0xFFFFFFFFu;
        rh.ray.id[i] = unsigned(i);
        rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect8(valid, embree_->scene, &context, &rh);
    for (int i = 0; i < n; ++i) {
        if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID)
            hits[i] = std::nullopt;
        else
            hits[i] = surface(RayHit{rh.ray.tfar[i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i]});
    }
}

namespace {
// The point of triangle (a, b, c) closest to p, by the Voronoi region of
// the triangle p projects into (Ericson 2004, "Real-Time Collision
// Detection" §5.1.5): a vertex, an edge or the interior.
glm::vec3 closest_point_on_triangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                                    const glm::vec3& c) {
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.f && d2 <= 0.f) return a;
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.f && d4 <= d3) return b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.f && d1 >= 0.f && d3 <= 0.f) return a + ab * (d1 / (d1 - d3));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.f && d5 <= d6) return c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.f && d2 >= 0.f && d6 <= 0.f) return a + ac * (d2 / (d2 - d6));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.f && d4 - d3 >= 0.f && d5 - d6 >= 0.f)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const float denom = va + vb + vc;
    if (!(denom > 0.f)) return a;  // a degenerate triangle: its vertices stand for it
    return a + ab * (vb / denom) + ac * (vc / denom);
}

struct ClosestPointQuery {
    const TriangleMesh* mesh;
};

// Embree's callback for each triangle within the query's radius: shrinking
// the radius to the distance found prunes every farther subtree.
bool closest_point_callback(RTCPointQueryFunctionArguments* args) {
    const auto& q = *static_cast<const ClosestPointQuery*>(args->userPtr);
    const auto& tri = q.mesh->triangles[args->primID];
    const glm::vec3 p(args->query->x, args->query->y, args->query->z);
    const glm::vec3 nearest = closest_point_on_triangle(p, q.mesh->positions[tri[0]],
                                                        q.mesh->positions[tri[1]], q.mesh->positions[tri[2]]);
    const float d = glm::length(nearest - p);
    if (!(d < args->query->radius)) return false;
    args->query->radius = d;
    return true;
}
}  // namespace

float MeshAccel::distance_to_surface(const glm::vec3& p, float max_distance) const {
    RTCPointQuery query;
    query.x = p.x;
    query.y = p.y;
    query.z = p.z;
    query.time = 0.f;
    query.radius = max_distance;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    ClosestPointQuery user{&mesh_};
    rtcPointQuery(embree_->scene, &query, &context, closest_point_callback, &user);
    return std::min(query.radius, max_distance);
}

SurfaceHit MeshAccel::surface(const RayHit& ray_hit) const {
    const float u = ray_hit.u, v = ray_hit.v;
    SurfaceHit hit;
    hit.t = ray_hit.t;
    hit.primitive = ray_hit.primitive;
    hit.u = u;
    hit.v = v;
    // Our own face normal, (p1 - p0) x (p2 - p0), whose orientation we define.
    const TriangleShading& ts = shading_[ray_hit.primitive];
    hit.geometric_normal = ts.face;
    hit.shading_normal = hit.geometric_normal;
    if (!flat_) {
        const glm::vec3 n = (1.f - u - v) * ts.normal[0] + u * ts.normal[1] + v * ts.normal[2];
        const float len = glm::length(n);
        if (len > 1e-6f) hit.shading_normal = n / len;
    }
    return hit;
}

std::optional<SurfaceHit> MeshAccel::intersect_primitive(const glm::vec3& o, const glm::vec3& d,
                                                        std::uint32_t triangle) const {
    const auto& tri = mesh_.triangles[triangle];
    const glm::vec3& p0 = mesh_.positions[tri[0]];
    const glm::vec3 e1 = mesh_.positions[tri[1]] - p0, e2 = mesh_.positions[tri[2]] - p0;
    const glm::vec3 pv = glm::cross(d, e2);
    const float det = glm::dot(e1, pv);
    if (!(std::abs(det) > 0.f)) return std::nullopt;
    const glm::vec3 tv = o - p0;
    const float u = glm::dot(tv, pv) / det;
    const glm::vec3 qv = glm::cross(tv, e1);
    const float v = glm::dot(d, qv) / det;
    const float t = glm::dot(e2, qv) / det;
    if (!(u >= 0.f && v >= 0.f && u + v <= 1.f && t > 0.f)) return std::nullopt;
    return surface(RayHit{t, triangle, u, v});
}

// The unit normal n = ñ / |ñ| varies as dn = (I − n nᵀ) dñ / |ñ|, dñ from
// the triangle's frame (triangle_frame).
SurfaceDifferential MeshAccel::differential(const SurfaceHit& hit) const {
    SurfaceDifferential sd;
    const TriangleFrame& f = frames_[hit.primitive];
    sd.tangent[0] = f.tangent[0];
    sd.tangent[1] = f.tangent[1];
    if (flat_ || f.tangent[0] == glm::vec3(0.f)) return sd;
    const TriangleShading& ts = shading_[hit.primitive];
    const glm::vec3 nt = (1.f - hit.u - hit.v) * ts.normal[0] + hit.u * ts.normal[1] + hit.v * ts.normal[2];
    const float len = glm::length(nt);
    if (!(len > 1e-6f)) return sd;  // the shading normal fell back to the face's
    const glm::vec3 n = nt / len;
    for (int k = 0; k < 2; ++k) sd.dn[k] = (f.dn[k] - n * glm::dot(n, f.dn[k])) / len;
    return sd;
}

}  // namespace jade
