#pragma once
// A render as a document: scene, medium, camera, lights, settings and
// outputs as plain data, read from and written to JSON. report.json embeds
// the pipeline's final render as one; `jaderender render --job FILE` replays
// it (flags given beside it override single keys). Paths in a document are
// relative to the document's folder, as in Mitsuba's scene files.

#include "jade/io/vdb_io.h"
#include "jade/render/dielectric.h"
#include "jade/render/renderer.h"

#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <string>

namespace jade {

struct RenderJob {
    // Scene
    std::string mesh;                          // .obj / .gltf / .glb
    // Or an analytic sphere, centre x, y, z and radius (Mitsuba's and pbrt's
    // `sphere` shape; geometry/sphere_boundary.h).
    std::optional<std::array<float, 4>> sphere;
    bool flat_normals = false;                 // shade with face normals
    bool allow_open = false;                   // render a badly open mesh anyway
    std::string volume;                        // .vdb: a jaderender volume or foreign grids
    std::optional<std::array<float, 3>> ks;    // override a jaderender volume's k_s
    std::optional<std::array<float, 3>> contrast;  // and its contrast
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

    // Light: by default a delta light (the paper's, §5.3) from just above
    // and to the right of the default camera's view (25° above the horizon,
    // 11° right; the camera looks down 20°), so that the stone the camera
    // sees is lit from the front as a photographed slab is, with little of
    // it in shade and no highlight of the light itself, and the form still
    // shows (README, "Defaults"; docs/design.md, "The default light").
    glm::vec3 light_direction{0.17f, 0.42f, 0.89f};  // toward the light
    float light_irradiance = 3.f;
    float light_radius_degrees = 0.f;
    // A .gltf/.glb whose first directional light (KHR_lights_punctual) sets
    // the direction and irradiance instead of the two above.
    std::string light_file;
    // True when light_direction and light_irradiance hold light_file's light
    // (a job written by jaderender after loading it), so that a reader
    // without a glTF parser (the Blender import) can use them.
    bool light_file_resolved = false;
    std::string environment = "0.01";          // "v", "r,g,b", or a lat-long image: a dim fill (README: "Defaults")
    float environment_scale = 1.f;
    std::string background;                    // image behind the object
    bool transparent = false;

    RenderSettings settings;
    std::string reference;                     // image to measure RMSE against

    // Outputs: out (.exr); "auto" puts the PNG beside it (same name) and
    // <name>.convergence.csv beside it; "" skips either.
    std::string out;
    std::string png = "auto";
    std::string convergence = "auto";
    // The PNG's exposure (render → display factor before sRGB): 0 = the one
    // a jaderender .vdb stores from its fit, else 1.
    float exposure = 0.f;
};

// A file beside `out` with its extension replaced by `suffix`:
// sibling_path("out/render.exr", ".png") = "out/render.png".
std::string sibling_path(const std::string& out, const std::string& suffix);

// The job as JSON text, its paths made relative to `base_dir`.
std::string job_json(const RenderJob& job, const std::string& base_dir);
// Reads a job document: a file holding one (a "job" object, as report.json
// does) or being one. Relative paths are resolved against its folder.
// Throws jade::Error naming the file and the key.
RenderJob load_job(const std::string& path);
// Likewise from the document's text; `origin` names it in messages and
// relative paths are resolved against `base_dir`.
RenderJob parse_job(const std::string& text, const std::string& origin, const std::string& base_dir);

}  // namespace jade
