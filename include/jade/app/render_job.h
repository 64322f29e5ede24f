#pragma once
// `jaderender render`: everything one render needs, as plain options, turned
// into a scene (mesh, medium, lights, camera), rendered progressively and
// written out. The command-line front end only fills RenderJob.

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

struct RenderJob {
    // Scene
    std::string mesh;                          // .obj / .gltf / .glb
    bool flat_normals = false;                 // shade with face normals
    bool allow_open = false;                   // render a badly open mesh anyway
    std::string volume;                        // .vdb: a jaderender volume or foreign grids
    std::optional<std::array<float, 3>> ks;    // override a jaderender volume's k_s
    DensityConversion density;                 // for a foreign `density` grid
    std::optional<Spectrum> sigma_s, sigma_a;  // a homogeneous medium instead of a volume
    BoundaryParams interface;
    float g = 0.f;                             // Henyey–Greenstein asymmetry

    // Camera: from a glTF file's first camera when camera_file is set, else
    // framed from the mesh unless origin is given.
    std::string camera_file;
    std::optional<glm::vec3> camera_origin;
    glm::vec3 camera_target{0.f};
    bool camera_target_given = false;
    glm::vec3 camera_up{0.f, 1.f, 0.f};
    float fov_degrees = 40.f;                  // horizontal
    int width = 512, height = 512;

    // Light
    glm::vec3 light_direction{0.35f, 0.8f, 0.5f};  // toward the light: upper front right
    float light_irradiance = 3.f;
    float light_radius_degrees = 20.f;
    std::string environment = "0.01";          // "v", "r,g,b", or a lat-long image: a dim fill (README: "Defaults")
    float environment_scale = 1.f;
    std::string background;                    // image behind the object
    bool transparent = false;

    RenderSettings settings;
    std::string reference;                     // image to measure RMSE against

    // Outputs: out (.exr); "auto" puts the PNG beside it (same name) and
    // convergence.csv in its folder; "" skips either.
    std::string out;
    std::string png = "auto";
    std::string convergence = "auto";
};

struct RenderJobResult {
    RenderResult render;
    std::vector<std::string> warnings;  // e.g. an open mesh
    std::vector<std::string> written;   // files, in the order written
    std::string medium_description;
    std::size_t medium_bytes = 0;
    double load_seconds = 0.0;
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
