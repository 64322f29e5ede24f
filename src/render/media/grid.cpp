#include "jade/render/media/grid.h"

#include "jade/core/error.h"

#include <glm/common.hpp>
#include <tbb/parallel_reduce.h>
#include <tbb/blocked_range.h>

#include <cmath>
#include <limits>

namespace jade {

TrilinearStencil trilinear_stencil(const GridPlacement& g, const glm::vec3& p) {
    int i0[3], i1[3];
    float f[3];
    for (int a = 0; a < 3; ++a) {
        const float hi = float(g.size[a] - 1);
        const float x = std::clamp((p[a] - g.origin[a]) / g.spacing[a], 0.f, hi);
        const float fl = std::floor(x);
        i0[a] = int(fl);
        i1[a] = std::min(i0[a] + 1, g.size[a] - 1);
        f[a] = x - fl;
    }
    TrilinearStencil s;
    const std::size_t nx = std::size_t(g.size[0]), nxy = nx * std::size_t(g.size[1]);
    int n = 0;
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx, ++n) {
                s.index[n] = std::size_t(dz ? i1[2] : i0[2]) * nxy +
                             std::size_t(dy ? i1[1] : i0[1]) * nx + std::size_t(dx ? i1[0] : i0[0]);
                s.weight[n] = (dx ? f[0] : 1.f - f[0]) * (dy ? f[1] : 1.f - f[1]) *
                              (dz ? f[2] : 1.f - f[2]);
            }
    return s;
}

// ---------------------------------------------------------------------------

MaterialVolumeMedium::MaterialVolumeMedium(const MaterialVolume& volume, const Cube& cube,
                                           const Spectrum& majorant_floor)
    : MaterialVolumeMedium(volume, cube, volume.optics, majorant_floor) {}

MaterialVolumeMedium::MaterialVolumeMedium(const MaterialVolume& volume, const Cube& cube,
                                           const OpticalParams& optics, const Spectrum& majorant_floor)
    : volume_(volume), grid_(GridPlacement::of_cube(volume.resolution, cube)),
      table_(optics, cube.side) {
    if (volume.levels.size() != grid_.voxels())
        throw Error("internal: material volume has the wrong number of voxels");
    // The majorant and minorant are the largest and smallest σ_t over the
    // levels that actually occur (trilinear weights are non-negative and
    // sum to 1, so every lookup lies between them).
    using Used = std::array<std::array<bool, 256>, 3>;
    const Used used = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, volume.levels.size(), 1 << 16), Used{},
        [&](const tbb::blocked_range<std::size_t>& r, Used u) {
            for (std::size_t i = r.begin(); i != r.end(); ++i)
                for (int c = 0; c < 3; ++c) u[c][volume.levels[i][c]] = true;
            return u;
        },
        [](Used a, const Used& b) {
            for (int c = 0; c < 3; ++c)
                for (int l = 0; l < 256; ++l) a[c][l] = a[c][l] || b[c][l];
            return a;
        });
    majorant_ = Spectrum(0.f);
    minorant_ = Spectrum(std::numeric_limits<float>::infinity());
    for (int c = 0; c < 3; ++c)
        for (int l = 0; l < 256; ++l)
            if (used[c][l]) {
                const float sigma_t = table_.sigma_s[c][l] + table_.sigma_a[c][l];
                majorant_[c] = std::max(majorant_[c], sigma_t);
                minorant_[c] = std::min(minorant_[c], sigma_t);
            }
    majorant_ = glm::max(majorant_, majorant_floor);
}

MediumProperties MaterialVolumeMedium::at(const glm::vec3& p) const {
    const TrilinearStencil st = trilinear_stencil(grid_, p);
    MediumProperties m;
    for (int n = 0; n < 8; ++n) {
        const Rgb8& lv = volume_.levels[st.index[n]];
        const float w = st.weight[n];
        for (int c = 0; c < 3; ++c) {
            m.sigma_s[c] += w * table_.sigma_s[c][lv[c]];
            m.sigma_a[c] += w * table_.sigma_a[c][lv[c]];
        }
    }
    return m;
}

std::size_t MaterialVolumeMedium::memory_bytes() const {
    return volume_.levels.size() * sizeof(Rgb8) + sizeof(table_);
}

// ---------------------------------------------------------------------------

FloatGridMedium::FloatGridMedium(CoefficientGrids grids) : grids_(std::move(grids)) {
    const GridPlacement& g = grids_.placement;
    if (g.size[0] < 1 || g.size[1] < 1 || g.size[2] < 1 || grids_.sigma_s.size() != g.voxels() ||
        grids_.sigma_a.size() != g.voxels())
        throw Error("internal: coefficient grids do not match their placement");
    for (int a = 0; a < 3; ++a)
        if (!(g.spacing[a] > 0.f)) throw Error("a medium grid's voxel size must be positive");
    for (std::size_t i = 0; i < g.voxels(); ++i) {
        const Spectrum& s = grids_.sigma_s[i];
        const Spectrum& a = grids_.sigma_a[i];
        if (!is_finite(s + a) || s.x < 0.f || s.y < 0.f || s.z < 0.f || a.x < 0.f || a.y < 0.f ||
            a.z < 0.f)
            throw Error("medium grid holds a negative or non-finite coefficient");
        majorant_ = glm::max(majorant_, s + a);
        minorant_ = glm::min(minorant_, s + a);
    }
    majorant_grid_ = MajorantGrid(g, kMajorantCellVoxels,
                                  [&](std::size_t i) { return grids_.sigma_s[i] + grids_.sigma_a[i]; });
}

MediumProperties FloatGridMedium::at(const glm::vec3& p) const {
    const TrilinearStencil st = trilinear_stencil(grids_.placement, p);
    MediumProperties m;
    for (int n = 0; n < 8; ++n) {
        m.sigma_s += st.weight[n] * grids_.sigma_s[st.index[n]];
        m.sigma_a += st.weight[n] * grids_.sigma_a[st.index[n]];
    }
    return m;
}

std::size_t FloatGridMedium::memory_bytes() const {
    return (grids_.sigma_s.size() + grids_.sigma_a.size()) * sizeof(Spectrum) + majorant_grid_.memory_bytes();
}

}  // namespace jade
