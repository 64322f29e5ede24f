#pragma once
// Reading meshes and cameras from files: OBJ (tinyobjloader) and glTF/GLB
// (tinygltf), validated before anything else sees them.

#include "jade/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <string>

namespace jade {

// Loads .obj, .gltf or .glb (every triangle primitive of the default scene,
// node transforms applied). Throws jade::Error naming the file when it cannot
// be read, has no triangle, or has a NaN/infinite coordinate.
TriangleMesh load_mesh(const std::string& path);

// The checks load_mesh applies to every format: at least one triangle of
// non-zero area, finite coordinates (binary glTF can carry NaN), a size
// between kMinMeshSize and kMaxMeshSize, and not so far from the origin
// that single precision cannot resolve it. Throws jade::Error naming
// mesh.path.
void validate_mesh(const TriangleMesh& mesh);

// The sizes (longest side of the bounding box, in world units) a mesh may
// have. Embree and the renderer's ray offsets work in single precision:
// measured, a mesh scaled to 1e-10…1e-16 or 1e13…1e15 of a unit made
// Embree abort, and at 1e-20 the object vanished; products of three
// coordinates must stay far inside float's range (1e-38…3e38).
constexpr float kMinMeshSize = 1e-6f;
constexpr float kMaxMeshSize = 1e7f;
// And its size relative to its farthest coordinate: below this the ray
// offsets (1e-5 of the size) fall under a float's resolution there.
constexpr float kMinMeshSizePerReach = 1e-3f;

// The first perspective camera of a glTF scene (depth-first over the default
// scene's nodes), in world space: glTF cameras look along their node's −z
// with +y up, and give a VERTICAL field of view.
struct FileCamera {
    glm::vec3 origin{0.f}, forward{0.f, 0.f, -1.f}, up{0.f, 1.f, 0.f};
    float yfov_radians = 0.8f;
};
// Throws jade::Error naming the file when it cannot be read or holds no
// perspective camera.
FileCamera load_gltf_camera(const std::string& path);

// The first directional light of a glTF scene (KHR_lights_punctual,
// depth-first over the default scene's nodes), in world space: it shines
// along its node's −z, so `toward` (the direction to the light) is its +z.
// `irradiance` is its intensity (lux) times the mean of its colour;
// `coloured` says the colour was not grey (the renderer's light is white).
struct FileLight {
    glm::vec3 toward{0.f, 0.f, 1.f};
    float irradiance = 1.f;
    bool coloured = false;
    std::string name;
};
// Throws jade::Error naming the file when it cannot be read or holds no
// directional light.
FileLight load_gltf_directional_light(const std::string& path);

}  // namespace jade
