#pragma once
// Axis-aligned boxes: a mesh's bounds, and the cube a material volume fills.

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <array>

namespace jade {

struct Bounds3 {
    glm::vec3 min{1e30f};
    glm::vec3 max{-1e30f};
    void extend(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    glm::vec3 centre() const { return 0.5f * (min + max); }
    glm::vec3 extent() const { return max - min; }
    bool contains(const glm::vec3& p) const {
        return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y && p.z <= max.z;
    }
};

// The cube the volume fills: around the mesh's bounding box, side = its
// longest extent, centred (docs/design.md, "Units"). Without a mesh, the unit
// cube at the origin.
struct Cube {
    std::array<double, 3> min{-0.5, -0.5, -0.5};
    double side = 1.0;
};

}  // namespace jade
