#pragma once
// Majorants along a ray for delta and ratio tracking (render/tracking.h).
//
// A coarse grid of majorants over a voxel grid (as pbrt-v4's MajorantGrid):
// each cell holds, per channel, the largest extinction any trilinear lookup
// inside it can return, so tracking draws tentative collisions against the
// local majorant instead of the whole grid's. In a medium whose extinction
// varies, the global majorant makes most tentative collisions null, and each
// costs a lookup (docs/design.md, "Majorant grid").
//
// Cells are `cell_voxels` voxels a side, laid from the centre of voxel
// (0, 0, 0) in the grid's own voxel coordinates. A lookup clamps to the
// grid's edge, so the outermost cells reach outward without end: a ray
// outside the grid still meets only the majorants of the voxels it reads.

#include "jade/core/spectrum.h"
#include "jade/volume/coefficient_grids.h"

#include <glm/vec3.hpp>

#include <array>
#include <functional>
#include <limits>
#include <vector>

namespace jade {

// A stretch [t_min, t_max) of a ray over which σ_t ≤ sigma_maj, per channel.
struct MajorantSegment {
    float t_min = 0.f, t_max = 0.f;
    Spectrum sigma_maj{0.f};
};

class MajorantGrid {
public:
    MajorantGrid() = default;
    // `sigma_t(i)`: the extinction of voxel i (flat index, x fastest).
    MajorantGrid(const GridPlacement& grid, int cell_voxels,
                 const std::function<Spectrum(std::size_t)>& sigma_t);

    const std::array<int, 3>& cells() const { return cells_; }
    const Spectrum& cell(int i, int j, int k) const {
        return majorants_[(std::size_t(k) * cells_[1] + j) * cells_[0] + i];
    }
    const glm::vec3& origin() const { return origin_; }        // the first cell's lower corner
    const glm::vec3& cell_size() const { return cell_size_; }  // world size along x, y, z
    const glm::vec3& inverse_cell_size() const { return inverse_cell_size_; }
    std::size_t memory_bytes() const { return majorants_.size() * sizeof(Spectrum); }

private:
    glm::vec3 origin_{0.f};
    glm::vec3 cell_size_{1.f}, inverse_cell_size_{1.f};
    std::array<int, 3> cells_{0, 0, 0};
    std::vector<Spectrum> majorants_;  // (k * ny + j) * nx + i
};

// The majorant segments of o + t·d in order from t = 0: the cells of a
// grid as a 3D DDA walks them (one cell a step; the crossing distances
// advance by a constant per axis, and the cell is an integer, so rounding
// never puts a point in the wrong cell), or one segment of the medium's
// global majorant when there is no grid.
class MajorantIterator {
public:
    MajorantIterator(const MajorantGrid* grid, const Spectrum& global, const glm::vec3& o,
                     const glm::vec3& d);
    // False when the walk has reached t_to; else the next non-empty segment,
    // cut at t_to (the walk then resumes there at the next call).
    bool next(MajorantSegment& seg, float t_to);

private:
    const MajorantGrid* grid_;
    Spectrum global_;
    float t_ = 0.f;
    int cell_[3] = {0, 0, 0}, step_[3] = {0, 0, 0}, last_[3] = {0, 0, 0};
    float next_crossing_[3] = {0.f, 0.f, 0.f}, delta_[3] = {0.f, 0.f, 0.f};
};

inline bool MajorantIterator::next(MajorantSegment& seg, float t_to) {
    if (!grid_) {
        if (!(t_ < t_to)) return false;
        seg = {t_, t_to, global_};
        t_ = t_to;
        return true;
    }
    while (t_ < t_to) {
        // The axis whose boundary comes first ends this cell.
        const int a = next_crossing_[0] < next_crossing_[1]
                          ? (next_crossing_[0] < next_crossing_[2] ? 0 : 2)
                          : (next_crossing_[1] < next_crossing_[2] ? 1 : 2);
        const float begin = t_;
        const Spectrum& maj = grid_->cell(cell_[0], cell_[1], cell_[2]);
        if (next_crossing_[a] < t_to) {
            t_ = next_crossing_[a];
            cell_[a] += step_[a];
            next_crossing_[a] = cell_[a] == last_[a] ? std::numeric_limits<float>::infinity()
                                                     : next_crossing_[a] + delta_[a];
        } else {
            t_ = t_to;
        }
        if (t_ > begin) {
            seg = {begin, t_, maj};
            return true;
        }
    }
    return false;
}

}  // namespace jade
