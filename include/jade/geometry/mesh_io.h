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

// The checks load_mesh applies to every format: at least one triangle,
// finite coordinates (binary glTF can carry NaN), non-zero size. Throws
// jade::Error naming mesh.path.
void validate_mesh(const TriangleMesh& mesh);

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

}  // namespace jade
