#pragma once
// Media sampled from dense voxel grids, with OpenVDB's placement convention:
// voxel (i, j, k) is centred at world origin + (i, j, k) ⊙ spacing. Lookup is
// trilinear between voxel centres, clamped at the edges (an edge voxel's value
// extends outward), as Mitsuba's gridvolume and Blender do. Trilinear weights
// are non-negative, so the largest voxel value is a valid majorant.

#include "jade/volume/coefficient_grids.h"
#include "jade/volume/material_volume.h"
#include "jade/render/medium.h"

#include <array>
#include <limits>
#include <vector>

namespace jade {

// Corner voxels and weights of a trilinear lookup.
struct TrilinearStencil {
    std::array<std::size_t, 8> index;
    std::array<float, 8> weight;
};
TrilinearStencil trilinear_stencil(const GridPlacement& grid, const glm::vec3& p);

// The material volume as a medium: 3 bytes a voxel (its levels) and a
// 256-entry coefficient table per channel, so a 256³ volume costs 50 MB.
// Placing the volume on another cube (another mesh) keeps its optical
// thickness per object size: the table is built for that cube's side.
// The volume's levels are referenced, not copied: it must outlive the medium.
class MaterialVolumeMedium final : public Medium {
public:
    // majorant_floor raises the majorant (never lowers it below the true
    // one): renders that share a majorant share every tentative collision,
    // which keeps renders at nearby coefficients correlated (the fitter's use).
    MaterialVolumeMedium(const MaterialVolume& volume, const Cube& cube,
                         const Spectrum& majorant_floor = Spectrum(0.f));
    // The same levels under other optical parameters (e.g. a k_s the fit
    // tries), without touching the volume.
    MaterialVolumeMedium(const MaterialVolume& volume, const Cube& cube, const OpticalParams& optics,
                         const Spectrum& majorant_floor = Spectrum(0.f));
    MediumProperties at(const glm::vec3& p) const override;
    Spectrum majorant() const override { return majorant_; }
    Spectrum minorant() const override { return minorant_; }
    std::size_t memory_bytes() const override;
    const GridPlacement& placement() const { return grid_; }

private:
    const MaterialVolume& volume_;
    GridPlacement grid_;
    CoefficientTable table_;
    Spectrum majorant_, minorant_;
};

// Float grids of σ_s and σ_a (a foreign .vdb's, e.g. scene C's), tracked
// against a majorant grid: their extinction varies freely, where the
// material volume's default is one extinction. Cells of 4 voxels a side:
// on scene C (64³) cells of 2, 4 and 8 voxels left 15, 22 and 37 % of the
// null collisions the global majorant draws, and 4 cost least time for the
// error (docs/design.md, "Majorant grid").
constexpr int kMajorantCellVoxels = 4;
class FloatGridMedium final : public Medium {
public:
    explicit FloatGridMedium(CoefficientGrids grids);  // throws for negative or non-finite values
    MediumProperties at(const glm::vec3& p) const override;
    Spectrum majorant() const override { return majorant_; }
    Spectrum minorant() const override { return minorant_; }
    const MajorantGrid* majorant_grid() const override { return &majorant_grid_; }
    std::size_t memory_bytes() const override;
    const GridPlacement& placement() const { return grids_.placement; }

private:
    CoefficientGrids grids_;
    Spectrum majorant_{0.f}, minorant_{std::numeric_limits<float>::infinity()};
    MajorantGrid majorant_grid_;
};

}  // namespace jade
