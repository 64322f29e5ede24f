#pragma once
// `jaderender render`: a job (app/job.h) turned into a scene (mesh, medium,
// lights, camera), rendered progressively and written out.

#include "jade/app/job.h"
#include "jade/render/camera.h"
#include "jade/render/dielectric.h"
#include "jade/geometry/mesh_accel.h"
#include "jade/render/scene.h"
#include "jade/render/renderer.h"
#include "jade/io/vdb_io.h"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace jade {

struct RenderJobResult {
    RenderResult render;
    std::vector<std::string> warnings;  // e.g. an open mesh
    std::vector<std::string> written;   // files, in the order written
    std::string medium_description;
    std::size_t medium_bytes = 0;
    double load_seconds = 0.0;
    float exposure = 1.f;               // the PNG's: the job's, the volume's fitted one, or 1
};

// Validates the job, loads everything, renders, writes the outputs (each whole
// or not at all). Throws jade::Error with one line naming the bad input.
RenderJobResult run_render_job(const RenderJob& job, Progress* progress = nullptr,
                               const std::function<void(const PassRecord&)>& on_pass = nullptr);

// What a scene references, owned in one place: the mesh and its BVH, the
// background image, the scene (lights, boundary; its medium left to the
// caller) and the camera's parameters.
struct PreparedScene {
    TriangleMesh mesh;
    std::unique_ptr<MeshAccel> accel;
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
