#include "jade/geometry/clearance_grid.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace jade {

namespace {

constexpr float kFar = std::numeric_limits<float>::infinity();

// Exact 1D squared distance transform of f along n samples with stride
// `stride` (Felzenszwalb & Huttenlocher's lower envelope of parabolas):
// f[q] ← min_p (f[p] + (q − p)²). Scratch space is passed in.
void distance_transform_1d(float* f, int n, std::size_t stride, std::vector<float>& g,
                           std::vector<int>& v, std::vector<float>& z) {
    for (int q = 0; q < n; ++q) g[q] = f[q * stride];
    int k = -1;
    for (int q = 0; q < n; ++q) {
        if (g[q] == kFar) continue;
        for (;;) {
            if (k < 0) {
                v[0] = q;
                z[0] = -kFar;
                k = 0;
                break;
            }
            const int p = v[k];
            const float s = ((g[q] + float(q) * q) - (g[p] + float(p) * p)) / (2.f * float(q - p));
            if (s <= z[k]) {
                --k;
                continue;
            }
            ++k;
            v[k] = q;
            z[k] = s;
            break;
        }
    }
    if (k < 0) return;  // nothing marked on this line
    z[k + 1] = kFar;
    int j = 0;
    for (int q = 0; q < n; ++q) {
        while (z[j + 1] < float(q)) ++j;
        const float d = float(q - v[j]);
        f[q * stride] = d * d + g[v[j]];
    }
}

}  // namespace

ClearanceGrid::ClearanceGrid(const TriangleMesh& mesh, int cells) {
    const Bounds3 box = mesh.bounds();
    const glm::vec3 e = box.extent();
    const float longest = std::max({e.x, e.y, e.z});
    if (!(longest > 0.f) || !std::isfinite(longest) || cells < 1) return;
    h_ = longest / float(cells);
    inv_h_ = 1.f / h_;
    origin_ = box.min - glm::vec3(h_);
    for (int k = 0; k < 3; ++k) n_[k] = int(std::ceil(e[k] * inv_h_)) + 2;
    const std::size_t nx = n_[0], nxy = std::size_t(n_[0]) * n_[1];
    std::vector<float> f(nxy * n_[2], kFar);

    // Mark the cells of surface samples: lines parallel to bc at most h/2
    // apart, points on each at most h/2 apart, so every point of the triangle
    // is within h/2 + h/4 of a sample.
    const float step = 0.5f * h_;
    auto mark = [&](const glm::vec3& p) {
        const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor((p - origin_) * inv_h_)), glm::ivec3(0),
                                        glm::ivec3(n_[0] - 1, n_[1] - 1, n_[2] - 1));
        f[c.z * nxy + c.y * nx + c.x] = 0.f;
    };
    for (const auto& tri : mesh.triangles) {
        const glm::vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
        const int lines = std::max(1, int(std::ceil(std::max(glm::length(b - a), glm::length(c - a)) / step)));
        for (int i = 0; i <= lines; ++i) {
            const float s = float(i) / float(lines);
            const glm::vec3 p = a + s * (b - a), q = a + s * (c - a);
            const int points = std::max(1, int(std::ceil(glm::length(q - p) / step)));
            for (int j = 0; j <= points; ++j) mark(p + (float(j) / float(points)) * (q - p));
        }
    }

    // Separable exact transform: along x, then y, then z.
    const int longest_axis = std::max({n_[0], n_[1], n_[2]});
    auto pass = [&](int axis, int lines_a, int lines_b, std::size_t stride, std::size_t stride_a,
                    std::size_t stride_b) {
        tbb::parallel_for(0, lines_b, [&](int jb) {
            std::vector<float> g(longest_axis), z(longest_axis + 1);
            std::vector<int> v(longest_axis);
            for (int ja = 0; ja < lines_a; ++ja)
                distance_transform_1d(&f[jb * stride_b + ja * stride_a], n_[axis], stride, g, v, z);
        });
    };
    pass(0, n_[1], n_[2], 1, nx, nxy);
    pass(1, n_[0], n_[2], nx, 1, nxy);
    pass(2, n_[0], n_[1], nxy, 1, nx);

    // Stored in quarter cells, rounded down, one byte a cell: the grid is
    // read at every collision, and a quarter of the float grid's size stays
    // in cache (the float grid's loads were an eighth of a render).
    const float loss = 0.5f * std::sqrt(3.f) + 0.75f;  // in cells
    centre_bound_.resize(f.size());
    for (std::size_t i = 0; i < f.size(); ++i) {
        const float cells_clear = f[i] == kFar ? 0.f : std::sqrt(f[i]) - loss;
        centre_bound_[i] = std::uint8_t(std::clamp(std::floor(4.f * cells_clear), 0.f, 255.f));
    }
    quarter_h_ = 0.25f * h_;
}

float ClearanceGrid::at(const glm::vec3& p) const {
    const glm::vec3 u = (p - origin_) * inv_h_;
    // Compare in float before converting: a NaN or a far point is outside.
    if (!(u.x >= 0.f && u.y >= 0.f && u.z >= 0.f && u.x < float(n_[0]) && u.y < float(n_[1]) &&
          u.z < float(n_[2])))
        return 0.f;
    const int x = int(u.x), y = int(u.y), z = int(u.z);
    const std::uint8_t quarters = centre_bound_[(std::size_t(z) * n_[1] + y) * n_[0] + x];
    if (quarters == 0) return 0.f;
    const float d = quarter_h_ * float(quarters);
    const glm::vec3 c = origin_ + h_ * (glm::vec3(x, y, z) + 0.5f);
    return std::max(0.f, d - glm::length(p - c));
}

}  // namespace jade
