#pragma once
// Triangle meshes: the object's boundary (paper §5.3), with per-vertex
// normals (a file's, or area-weighted face normals). Reading files is in
// mesh_io.h, topology checks in topology.h.

#include "jade/core/bounds.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace jade {

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

// The volume a closed mesh encloses, by the divergence theorem (Σ p0·(p1 × p2) / 6
// over its triangles): negative when its triangles face inward.
double signed_volume(const TriangleMesh& mesh);
// The total area of the mesh's triangles.
double surface_area(const TriangleMesh& mesh);
// The mean length of the chords that random straight lines cut through a
// closed mesh: 4V/A (Cauchy's formula; it holds for any body, convex or not,
// when every piece of a line inside it counts as a chord).
double mean_chord_length(const TriangleMesh& mesh);
// Turns every triangle (and the normals with it) inside out.
void reverse_orientation(TriangleMesh& mesh);

// A sphere of `radius` at the origin: the icosahedron subdivided `level`
// times (20 * 4^level triangles), vertices on the sphere, exact normals.
TriangleMesh icosphere(int level, float radius);

// Area-weighted vertex normals, smooth across vertices that share a position
// (files split vertices along UV seams).
void compute_vertex_normals(TriangleMesh& mesh);

// The cube the material volume fills around a mesh (docs/design.md, "Units"): centred on the
// bounding box, side = its longest extent.
Cube bounding_cube(const TriangleMesh& mesh);
// The same about a box (an analytic shape's).
Cube bounding_cube(const Bounds3& bounds);

}  // namespace jade
