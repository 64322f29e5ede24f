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

}  // namespace jade
