#pragma once
// Clearance: a lower bound on the distance from a point to the object's
// surface. A free flight that stays within the clearance cannot reach the
// boundary, so it needs no ray query (docs/design.md, "Clearance"; the bound
// sphere tracing steps by).
//
// Built without any ray queries: the surface is sampled densely enough that
// every surface point lies within 3/4 of a cell of a sample, the cells
// holding samples are marked, and an exact Euclidean distance transform
// (Felzenszwalb & Huttenlocher 2012) gives every cell centre its distance to
// the nearest marked centre. A surface point lies in some marked cell, so
// distance(centre) ≥ transform − (half a cell diagonal + 3/4 of a cell).

#include "jade/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace jade {

class ClearanceGrid {
public:
    ClearanceGrid() = default;  // empty: every clearance is 0
    // Cubic cells, `cells` along the mesh's longest side, plus one cell of
    // padding around it.
    ClearanceGrid(const TriangleMesh& mesh, int cells);

    // At most the distance from p to the surface (the distance is
    // 1-Lipschitz: d(p) ≥ d(c) − |p − c| for the centre c of p's cell);
    // 0 outside the grid.
    float at(const glm::vec3& p) const;
    // Side of a cell: near the surface the bound is no better than this.
    float cell_size() const { return h_; }

private:
    glm::vec3 origin_{0.f};
    float h_ = 0.f, inv_h_ = 0.f, quarter_h_ = 0.f;
    int n_[3] = {0, 0, 0};
    std::vector<std::uint8_t> centre_bound_;  // quarter cells, x fastest
};

}  // namespace jade
