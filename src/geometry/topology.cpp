#include "jade/geometry/topology.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <unordered_map>
#include <vector>

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

namespace {
// Union-find over triangles, for connectedness.
std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}
}  // namespace

bool is_convex(const TriangleMesh& mesh) {
    if (mesh.triangles.empty()) return false;
    std::map<std::array<float, 3>, std::uint32_t> id_of;
    std::vector<std::uint32_t> id(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const auto& p = mesh.positions[v];
        id[v] = id_of.try_emplace({p.x, p.y, p.z}, std::uint32_t(id_of.size())).first->second;
    }
    // Each welded edge and the triangles using it (two, or the mesh is not closed).
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> faces_of;
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        const std::uint32_t a = id[tri[0]], b = id[tri[1]], c = id[tri[2]];
        if (a == b || b == c || a == c) return false;
        for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
            faces_of[(std::uint64_t(std::min(u, v)) << 32) | std::max(u, v)].push_back(t);
    }
    const glm::vec3 e = mesh.bounds().extent();
    const float tolerance = 1e-6f * std::max({e.x, e.y, e.z});
    std::vector<std::uint32_t> parent(mesh.triangles.size());
    for (std::uint32_t t = 0; t < parent.size(); ++t) parent[t] = t;
    // Whether every vertex of triangle `other` lies on or behind t's plane.
    auto behind = [&](std::uint32_t t, std::uint32_t other) {
        const glm::vec3 n = glm::normalize(mesh.face_normal(t));
        const glm::vec3 p0 = mesh.positions[mesh.triangles[t][0]];
        for (std::uint32_t v : mesh.triangles[other])
            if (glm::dot(mesh.positions[v] - p0, n) > tolerance) return false;
        return true;
    };
    for (const auto& [edge, faces] : faces_of) {
        if (faces.size() != 2) return false;
        if (!behind(faces[0], faces[1]) || !behind(faces[1], faces[0])) return false;
        parent[root(parent, faces[0])] = root(parent, faces[1]);
    }
    const std::uint32_t first = root(parent, 0);
    for (std::uint32_t t = 1; t < parent.size(); ++t)
        if (root(parent, t) != first) return false;
    return true;
}

}  // namespace jade
