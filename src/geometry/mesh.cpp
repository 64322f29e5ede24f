#include "jade/geometry/mesh.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <unordered_map>

namespace jade {

Bounds3 TriangleMesh::bounds() const {
    Bounds3 b;
    for (const auto& p : positions) b.extend(p);
    return b;
}

glm::vec3 TriangleMesh::face_normal(std::size_t t) const {
    const auto& tri = triangles[t];
    const glm::vec3 p0 = positions[tri[0]], p1 = positions[tri[1]], p2 = positions[tri[2]];
    return glm::cross(p1 - p0, p2 - p0);
}

double surface_area(const TriangleMesh& mesh) {
    double a = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) a += glm::length(glm::dvec3(mesh.face_normal(t)));
    return a / 2.0;
}

double mean_chord_length(const TriangleMesh& mesh) {
    const double area = surface_area(mesh);
    return area > 0.0 ? 4.0 * std::abs(signed_volume(mesh)) / area : 0.0;
}

double signed_volume(const TriangleMesh& mesh) {
    // Relative to the bounding box's centre, so that a mesh far from the
    // origin does not lose the volume to cancellation.
    const glm::dvec3 c(mesh.bounds().centre());
    double v = 0;
    for (const auto& tri : mesh.triangles) {
        const glm::dvec3 p0 = glm::dvec3(mesh.positions[tri[0]]) - c;
        const glm::dvec3 p1 = glm::dvec3(mesh.positions[tri[1]]) - c;
        const glm::dvec3 p2 = glm::dvec3(mesh.positions[tri[2]]) - c;
        v += glm::dot(p0, glm::cross(p1, p2));
    }
    return v / 6.0;
}

void reverse_orientation(TriangleMesh& mesh) {
    for (auto& tri : mesh.triangles) std::swap(tri[1], tri[2]);
    for (auto& n : mesh.normals) n = -n;
}

// Area-weighted vertex normals over vertices welded by position, so a file
// that splits vertices along UV seams still gets smooth normals across them.
void compute_vertex_normals(TriangleMesh& mesh) {
    std::unordered_map<std::uint64_t, std::uint32_t> weld;
    std::vector<std::uint32_t> group(mesh.positions.size());
    auto key = [](const glm::vec3& p) {
        std::uint32_t b[3];
        std::memcpy(b, &p, sizeof b);
        return (std::uint64_t(b[0]) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(b[1]) * 0xC2B2AE3D27D4EB4Full) ^
               (std::uint64_t(b[2]) * 0x165667B19E3779F9ull);
    };
    std::vector<glm::vec3> representative;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        auto [it, fresh] = weld.try_emplace(key(mesh.positions[v]), std::uint32_t(representative.size()));
        // On a (vanishingly rare) hash collision of distinct positions, keep them apart.
        if (!fresh && representative[it->second] != mesh.positions[v]) {
            group[v] = std::uint32_t(representative.size());
            representative.push_back(mesh.positions[v]);
            continue;
        }
        if (fresh) representative.push_back(mesh.positions[v]);
        group[v] = it->second;
    }
    std::vector<glm::vec3> sum(representative.size(), glm::vec3(0.f));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::vec3 n = mesh.face_normal(t);  // length = twice the area
        for (std::uint32_t v : mesh.triangles[t]) sum[group[v]] += n;
    }
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::vec3 n = sum[group[v]];
        const float len = glm::length(n);
        mesh.normals[v] = len > 0.f ? n / len : glm::vec3(0.f, 0.f, 1.f);
    }
}


Cube bounding_cube(const TriangleMesh& mesh) { return bounding_cube(mesh.bounds()); }

Cube bounding_cube(const Bounds3& b) {
    const glm::vec3 c = b.centre(), e = b.extent();
    const double side = std::max({e.x, e.y, e.z});
    Cube cube;
    cube.side = side;
    for (int k = 0; k < 3; ++k) cube.min[k] = double(c[k]) - 0.5 * side;
    return cube;
}

TriangleMesh icosphere(int level, float radius) {
    TriangleMesh m;
    m.path = "(built-in icosphere, level " + std::to_string(level) + ")";
    const float t = (1.f + std::sqrt(5.f)) / 2.f;
    m.positions = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : m.positions) p = glm::normalize(p);
    m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            m.positions.push_back(glm::normalize(m.positions[a] + m.positions[b]));
            const auto i = std::uint32_t(m.positions.size() - 1);
            midpoint.emplace(key, i);
            return i;
        };
        std::vector<std::array<std::uint32_t, 3>> finer;
        for (const auto& tri : m.triangles) {
            const std::uint32_t a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
            finer.push_back({tri[0], a, c});
            finer.push_back({tri[1], b, a});
            finer.push_back({tri[2], c, b});
            finer.push_back({a, b, c});
        }
        m.triangles = std::move(finer);
    }
    m.normals = m.positions;
    for (auto& p : m.positions) p *= radius;
    m.file_normals = true;
    return m;
}

}  // namespace jade
