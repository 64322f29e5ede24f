#pragma once
// Media sampled from dense voxel grids, with OpenVDB's placement convention:
// voxel (i, j, k) is centred at world origin + (i, j, k) ⊙ spacing. Lookup is
// trilinear between voxel centres, clamped at the edges (an edge voxel's value
// extends outward), as Mitsuba's gridvolume and Blender do. Trilinear weights
// are non-negative, so the largest voxel value is a valid majorant.

#include "jade/material_volume.h"
#include "jade/medium.h"

#include <array>
#include <vector>

namespace jade {

// Where a grid's voxels sit in the world.
struct GridPlacement {
    std::array<int, 3> size{0, 0, 0};   // voxels along x, y, z
    glm::vec3 origin{0.f};              // world centre of voxel (0, 0, 0)
    glm::vec3 spacing{1.f};             // voxel size along x, y, z

    // The placement of an s³ material volume over `cube`.
    static GridPlacement of_cube(int resolution, const Cube& cube);
    std::size_t voxels() const { return std::size_t(size[0]) * size[1] * size[2]; }
};

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
    MediumProperties at(const glm::vec3& p) const override;
    Spectrum majorant() const override { return majorant_; }
    std::size_t memory_bytes() const override;
    const GridPlacement& placement() const { return grid_; }

private:
    const MaterialVolume& volume_;
    GridPlacement grid_;
    CoefficientTable table_;
    Spectrum majorant_;
};

// Float grids of σ_s and σ_a (per world unit), e.g. read from a foreign .vdb.
struct CoefficientGrids {
    GridPlacement placement;
    std::vector<Spectrum> sigma_s, sigma_a;  // index (k * ny + j) * nx + i
};

class FloatGridMedium final : public Medium {
public:
    explicit FloatGridMedium(CoefficientGrids grids);  // throws for negative or non-finite values
    MediumProperties at(const glm::vec3& p) const override;
    Spectrum majorant() const override { return majorant_; }
    std::size_t memory_bytes() const override;
    const GridPlacement& placement() const { return grids_.placement; }

private:
    CoefficientGrids grids_;
    Spectrum majorant_{0.f};
};

}  // namespace jade
