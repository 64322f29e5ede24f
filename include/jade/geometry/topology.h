#pragma once
// Whether a mesh encloses a volume: its edges after welding.

#include "jade/geometry/mesh.h"

#include <cstddef>

namespace jade {

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

// Whether the mesh bounds a convex body: closed, manifold, one connected
// piece, and convex at every edge (each triangle's far vertex lies on or
// behind its neighbour's plane, to 1e-6 of the mesh's size). A closed
// connected surface that is locally convex everywhere is convex (Tietze),
// so a ray that leaves it outward, from any point, never meets it again.
bool is_convex(const TriangleMesh& mesh);

}  // namespace jade
