#include "jade/render/majorant_grid.h"

#include "jade/core/error.h"

#include <glm/common.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace jade {

namespace {

// The cell along one axis that holds voxel coordinate u (clamped: the
// outermost cells reach outward), NaN included.
int cell_of(float u, int cells) {
    const float f = std::floor(u);
    if (f >= float(cells - 1)) return cells - 1;
    return f > 0.f ? int(f) : 0;
}

}  // namespace

MajorantGrid::MajorantGrid(const GridPlacement& grid, int cell_voxels,
                           const std::function<Spectrum(std::size_t)>& sigma_t) {
    if (cell_voxels < 1) throw Error("internal: a majorant cell spans at least one voxel");
    for (int a = 0; a < 3; ++a) {
        if (grid.size[a] < 1) throw Error("internal: a majorant grid over an empty voxel grid");
        // Voxel coordinates run from 0 to size − 1 between the outermost
        // centres; cells tile that span (at least one cell).
        cells_[a] = std::max(1, (grid.size[a] - 1 + cell_voxels - 1) / cell_voxels);
        cell_size_[a] = float(cell_voxels) * grid.spacing[a];
        inverse_cell_size_[a] = 1.f / cell_size_[a];
    }
    origin_ = grid.origin;
    majorants_.assign(std::size_t(cells_[0]) * cells_[1] * cells_[2], Spectrum(0.f));
    // A lookup at voxel coordinate x reads voxels ⌊x⌋ and ⌊x⌋ + 1, so cell c
    // (x in [cB, (c+1)B]) reads voxels cB to (c+1)B + 1. One voxel more on
    // each side keeps a point that rounds just outside its cell below the
    // majorant too.
    auto voxel_range = [&](int a, int c) {
        return std::array<int, 2>{std::max(0, c * cell_voxels - 1),
                                  std::min(grid.size[a] - 1, (c + 1) * cell_voxels + 1)};
    };
    const std::size_t nx = std::size_t(grid.size[0]), nxy = nx * std::size_t(grid.size[1]);
    tbb::parallel_for(0, cells_[2], [&](int ck) {
        const auto rz = voxel_range(2, ck);
        for (int cj = 0; cj < cells_[1]; ++cj) {
            const auto ry = voxel_range(1, cj);
            for (int ci = 0; ci < cells_[0]; ++ci) {
                const auto rx = voxel_range(0, ci);
                Spectrum m(0.f);
                for (int z = rz[0]; z <= rz[1]; ++z)
                    for (int y = ry[0]; y <= ry[1]; ++y)
                        for (int x = rx[0]; x <= rx[1]; ++x)
                            m = glm::max(m, sigma_t(std::size_t(z) * nxy + std::size_t(y) * nx + std::size_t(x)));
                majorants_[(std::size_t(ck) * cells_[1] + cj) * cells_[0] + ci] = m;
            }
        }
    });
}

MajorantIterator::MajorantIterator(const MajorantGrid* grid, const Spectrum& global,
                                   const glm::vec3& o, const glm::vec3& d)
    : grid_(grid), global_(global) {
    if (!grid_) return;
    constexpr float kInfinity = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
        const int n = grid_->cells()[a];
        const float origin = grid_->origin()[a], size = grid_->cell_size()[a];
        const int i = cell_of((o[a] - origin) * grid_->inverse_cell_size()[a], n);
        const float inv_d = 1.f / d[a];
        cell_[a] = i;
        // The boundary ahead: the cell's upper plane going up, its lower one
        // going down; the outermost cells have none outward. One that lies
        // at or behind o (o rounded into the cell) gives an empty first
        // segment, which next() skips.
        if (d[a] > 0.f) {
            step_[a] = 1;
            last_[a] = n - 1;
            delta_[a] = size * inv_d;
            next_crossing_[a] = i == n - 1 ? kInfinity : (origin + float(i + 1) * size - o[a]) * inv_d;
        } else if (d[a] < 0.f) {
            step_[a] = -1;
            last_[a] = 0;
            delta_[a] = -size * inv_d;
            next_crossing_[a] = i == 0 ? kInfinity : (origin + float(i) * size - o[a]) * inv_d;
        } else {
            last_[a] = i;
            delta_[a] = kInfinity;
            next_crossing_[a] = kInfinity;
        }
    }
}

}  // namespace jade
