#include "jade/geometry/topology.h"

#include <algorithm>
#include <array>
#include <map>
#include <unordered_map>

namespace jade {

MeshTopology mesh_topology(const TriangleMesh& mesh) {
    // Weld by exact position.
    std::map<std::array<float, 3>, std::uint32_t> id_of;
    std::vector<std::uint32_t> id(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const auto& p = mesh.positions[v];
        id[v] = id_of.try_emplace({p.x, p.y, p.z}, std::uint32_t(id_of.size())).first->second;
    }
    std::unordered_map<std::uint64_t, std::uint32_t> uses;
    MeshTopology topo;
    for (const auto& tri : mesh.triangles) {
        const std::uint32_t a = id[tri[0]], b = id[tri[1]], c = id[tri[2]];
        if (a == b || b == c || a == c) {
            ++topo.degenerate_triangles;
            continue;
        }
        for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
            ++uses[(std::uint64_t(std::min(u, v)) << 32) | std::max(u, v)];
    }
    topo.edges = uses.size();
    for (const auto& [edge, n] : uses) {
        topo.boundary_edges += n == 1;
        topo.nonmanifold_edges += n > 2;
    }
    return topo;
}

}  // namespace jade
