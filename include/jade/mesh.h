#pragma once
// Triangle meshes: the object's boundary (paper §5.3). Loaded from OBJ
// (tinyobjloader) or glTF/GLB (tinygltf), validated, with per-vertex normals
// (the file's when present, area-weighted face normals otherwise).

#include "jade/material_volume.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace jade {

struct Bounds3 {
    glm::vec3 min{1e30f};
    glm::vec3 max{-1e30f};
    void extend(const glm::vec3& p);
    glm::vec3 centre() const { return 0.5f * (min + max); }
    glm::vec3 extent() const { return max - min; }
};

struct TriangleMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // one per position, unit length
    std::vector<std::array<std::uint32_t, 3>> triangles;
    bool file_normals = false;       // true when the normals came from the file
    std::string path;

    Bounds3 bounds() const;
    // Unnormalised geometric normal of triangle t: (p1 - p0) x (p2 - p0),
    // outward for counter-clockwise winding seen from outside.
    glm::vec3 face_normal(std::size_t t) const;
};

// Loads .obj, .gltf or .glb (every triangle primitive of the default scene,
// node transforms applied). Throws jade::Error naming the file when it cannot
// be read, has no triangle, or has a NaN/infinite coordinate.
TriangleMesh load_mesh(const std::string& path);

// The checks load_mesh applies to every format: at least one triangle,
// finite coordinates (binary glTF can carry NaN), non-zero size. Throws
// jade::Error naming mesh.path.
void validate_mesh(const TriangleMesh& mesh);

// Topology of the surface after welding vertices at equal positions (files
// split vertices along normal or UV seams). A closed surface has every edge
// shared by exactly two triangles.
struct MeshTopology {
    std::size_t edges = 0;
    std::size_t boundary_edges = 0;     // used by one triangle: a hole
    std::size_t nonmanifold_edges = 0;  // used by three or more
    std::size_t degenerate_triangles = 0;
    bool closed() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
};
MeshTopology mesh_topology(const TriangleMesh& mesh);

// The first perspective camera of a glTF scene (depth-first over the default
// scene's nodes), in world space: glTF cameras look along their node's −z
// with +y up, and give a VERTICAL field of view.
struct FileCamera {
    glm::vec3 origin{0.f}, forward{0.f, 0.f, -1.f}, up{0.f, 1.f, 0.f};
    float yfov_radians = 0.8f;
};
// Throws jade::Error naming the file when it cannot be read or holds no
// perspective camera.
FileCamera load_gltf_camera(const std::string& path);

// A sphere of `radius` at the origin: the icosahedron subdivided `level`
// times (20 * 4^level triangles), vertices on the sphere, exact normals.
TriangleMesh icosphere(int level, float radius);

// The cube the material volume fills around a mesh (DESIGN §4): centred on the
// bounding box, side = its longest extent.
Cube bounding_cube(const TriangleMesh& mesh);

}  // namespace jade
