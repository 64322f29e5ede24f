#pragma once
// A job's scene set up for rendering: the mesh checked and its BVH built
// (or the analytic sphere),
// the lights, the background and the camera, owned in one place. Used by
// `jaderender render` and by the pipeline, which add their own medium.

#include "jade/app/job.h"
#include "jade/geometry/boundary.h"
#include "jade/geometry/mesh.h"
#include "jade/render/camera.h"
#include "jade/render/renderer.h"
#include "jade/render/scene.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace jade {

// What a scene references, owned in one place: the mesh and its boundary
// (for a sphere, a fine tessellation for what needs triangles: the preview,
// the .vdb's layout), the
// background image, the scene (lights, boundary; its medium left to the
// caller) and the camera's parameters.
struct PreparedScene {
    TriangleMesh mesh;
    std::unique_ptr<Boundary> boundary;   // a MeshAccel over `mesh`, or a SphereBoundary
    Cube cube;                            // the mesh's bounding cube, where a volume goes
    std::optional<Background> background;
    Backdrop backdrop;                    // what camera rays that miss see (the background's image)
    Scene scene;
    CameraParams camera;
    std::vector<std::string> warnings;    // e.g. an open mesh
};
// Loads and checks the mesh, lights and camera of a job (not its medium).
std::unique_ptr<PreparedScene> prepare_scene(const RenderJob& job);

}  // namespace jade
