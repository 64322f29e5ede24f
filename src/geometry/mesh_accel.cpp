#include "jade/geometry/mesh_accel.h"

#include "jade/core/error.h"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

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

MeshAccel::MeshAccel(const TriangleMesh& mesh, bool flat)
    : mesh_(mesh), flat_(flat), embree_(std::make_unique<Embree>()),
      clearance_(mesh, kClearanceCells) {
    face_normals_.reserve(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::vec3 n = mesh.face_normal(t);
        const float len = glm::length(n);
        face_normals_.push_back(len > 0.f ? n / len : glm::vec3(0.f));
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
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = o.x;
    rh.ray.org_y = o.y;
    rh.ray.org_z = o.z;
    rh.ray.dir_x = d.x;
    rh.ray.dir_y = d.y;
    rh.ray.dir_z = d.z;
    rh.ray.tnear = tmin;
    rh.ray.tfar = tmax;
    rh.ray.time = 0.f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

    SurfaceHit hit;
    hit.t = rh.ray.tfar;
    hit.triangle = rh.hit.primID;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    // Our own face normal, (p1 - p0) x (p2 - p0), whose orientation we define.
    hit.geometric_normal = face_normals_[hit.triangle];
    hit.shading_normal = hit.geometric_normal;
    if (!flat_) {
        const auto& tri = mesh_.triangles[hit.triangle];
        const glm::vec3 n = (1.f - hit.u - hit.v) * mesh_.normals[tri[0]] + hit.u * mesh_.normals[tri[1]] +
                            hit.v * mesh_.normals[tri[2]];
        const float len = glm::length(n);
        if (len > 1e-6f) hit.shading_normal = n / len;
    }
    return hit;
}

}  // namespace jade
