#include "jade/render/scene.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace jade {

void Scene::fit_ray_epsilon() {
    if (!boundary) return;
    const Bounds3 b = boundary->bounds();
    // Embree's hit points carry a float rounding error of a few ulps of the
    // coordinates' magnitude; 1e-5 of the scene's size lies far above it and
    // far below any feature a mesh resolves.
    const float size = glm::length(b.extent()) + glm::length(glm::max(glm::abs(b.min), glm::abs(b.max)));
    ray_epsilon = 1e-5f * size;
}

}  // namespace jade
