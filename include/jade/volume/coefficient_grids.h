#pragma once
// Voxel grids as plain data: where a grid's voxels sit in the world
// (OpenVDB's convention: voxel (i, j, k) is centred at origin + (i, j, k) ⊙
// spacing), and dense grids of coefficients per world unit, as a foreign .vdb
// holds them. The renderer samples them (render/media/grid.h); the .vdb
// reader fills them (io/vdb_io.h).

#include "jade/core/bounds.h"
#include "jade/core/spectrum.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
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

// Float grids of σ_s and σ_a (per world unit), e.g. read from a foreign .vdb.
struct CoefficientGrids {
    GridPlacement placement;
    std::vector<Spectrum> sigma_s, sigma_a;  // index (k * ny + j) * nx + i
};

}  // namespace jade
