#include "jade/volume/coefficient_grids.h"

namespace jade {

GridPlacement GridPlacement::of_cube(int resolution, const Cube& cube) {
    GridPlacement g;
    g.size = {resolution, resolution, resolution};
    const float h = float(cube.side / resolution);
    g.spacing = glm::vec3(h);
    g.origin = glm::vec3(float(cube.min[0]), float(cube.min[1]), float(cube.min[2])) + 0.5f * h;
    return g;
}

}  // namespace jade
