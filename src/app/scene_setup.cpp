#include "jade/app/scene_setup.h"

#include "jade/core/error.h"
#include "jade/core/parse.h"
#include "jade/geometry/mesh_accel.h"
#include "jade/geometry/mesh_io.h"
#include "jade/geometry/sphere_boundary.h"
#include "jade/geometry/topology.h"
#include "jade/io/image_io.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <optional>
#include <sstream>

namespace jade {

namespace {

// More than this share of open edges makes "inside" meaningless.
constexpr double kBadlyOpen = 0.01;

// A lat-long environment image, with its problems named after the file.
Environment environment_image(const std::string& path, float scale,
                              std::vector<std::string>& warnings) {
    if (!(scale >= 0.f) || !std::isfinite(scale)) throw Error("--env-scale must be non-negative");
    ImageF32 image = read_image_f32(path);
    std::optional<Environment> env;
    try {
        env.emplace(std::move(image), scale);
    } catch (const Error& e) {
        fail_file(path, e.what());
    }
    if (env->negative_texels() > 0) {
        std::ostringstream w;
        w << path << ": " << env->negative_texels() << " texel values of negative radiance (down to "
          << env->most_negative() << ") read as 0";
        warnings.push_back(w.str());
    }
    return *env;
}

// The icosphere level that stands in for an analytic sphere where triangles
// are needed (81 920 triangles, within 2e-4 of the radius inside it).
constexpr int kSphereTessellation = 6;

// The job's analytic sphere and its tessellation.
void prepare_sphere(const std::array<float, 4>& s, PreparedScene& prep) {
    const glm::vec3 centre(s[0], s[1], s[2]);
    try {
        prep.boundary = std::make_unique<SphereBoundary>(centre, s[3]);
    } catch (const Error& e) {
        throw Error(std::string("--sphere: ") + e.what());
    }
    prep.mesh = icosphere(kSphereTessellation, s[3]);
    for (glm::vec3& p : prep.mesh.positions) p += centre;
    // Held to a mesh's limits of size and place (single precision).
    prep.mesh.path = "--sphere";
    validate_mesh(prep.mesh);
}

// The job's mesh, checked (closed, outward) and its BVH built.
void prepare_mesh(const RenderJob& job, PreparedScene& prep) {
    prep.mesh = load_mesh(job.mesh);
    const MeshTopology topo = mesh_topology(prep.mesh);
    if (!topo.closed()) {
        const double share = double(topo.boundary_edges + topo.nonmanifold_edges) / double(topo.edges);
        std::ostringstream w;
        w << job.mesh << ": the mesh is not closed (" << topo.boundary_edges << " open and "
          << topo.nonmanifold_edges << " non-manifold of " << topo.edges
          << " edges); each triangle's front (outward) side is taken as outside, so paths may "
             "enter or leave the medium through the holes";
        if (share > kBadlyOpen && !job.allow_open)
            fail_file(job.mesh, "the mesh is badly open (" + std::to_string(topo.boundary_edges) +
                                    " of " + std::to_string(topo.edges) +
                                    " edges border a hole), so its inside is undefined; close it "
                                    "or pass --allow-open");
        prep.warnings.push_back(w.str());
    }
    // A closed mesh whose triangles face inward puts the medium outside it.
    if (topo.closed() && signed_volume(prep.mesh) < 0.0) {
        reverse_orientation(prep.mesh);
        prep.warnings.push_back(job.mesh + ": the mesh's triangles face inward (its volume is "
                                            "negative); their winding was reversed");
    }
    prep.boundary = std::make_unique<MeshAccel>(prep.mesh, job.flat_normals);
}

}  // namespace

std::unique_ptr<PreparedScene> prepare_scene(const RenderJob& job) {
    job.interface.validate();
    auto prep = std::make_unique<PreparedScene>();

    // Boundary.
    if (job.sphere)
        prepare_sphere(*job.sphere, *prep);
    else
        prepare_mesh(job, *prep);
    prep->cube = bounding_cube(prep->boundary->bounds());

    // Lights.
    Scene& scene = prep->scene;
    scene.boundary = prep->boundary.get();
    scene.interface = job.interface;
    scene.phase = PhaseFunction(job.g);
    glm::vec3 toward = job.light_direction;
    float irradiance = job.light_irradiance;
    if (!job.light_file.empty()) {
        const FileLight light = load_gltf_directional_light(job.light_file);
        toward = light.toward;
        irradiance = light.irradiance;
        if (light.coloured)
            prep->warnings.push_back(job.light_file + ": the light '" + light.name + "' is coloured; jaderender's "
                                     "light is white, so the colour's mean scales its intensity");
    }
    scene.light = DirectionalLight(toward, irradiance, job.light_radius_degrees);
    Spectrum env;
    if (parse_vec3(job.environment, env)) {
        scene.environment = Environment(env * job.environment_scale);
    } else {
        scene.environment = environment_image(job.environment, job.environment_scale, prep->warnings);
    }
    if (!job.background.empty()) {
        prep->background.emplace(read_image_f32(job.background));
        prep->backdrop.image = &*prep->background;
    }
    prep->backdrop.transparent = job.transparent;
    scene.fit_ray_epsilon();

    // Camera.
    CameraParams cam = frame_mesh(prep->boundary->bounds(), job.width, job.height, job.fov_degrees);
    if (!job.camera_file.empty()) {
        if (job.camera_origin || job.camera_target_given)
            throw Error("--camera-file cannot be combined with --camera-origin/--camera-target");
        cam = camera_from_file(load_gltf_camera(job.camera_file), job.width, job.height);
    }
    if (job.camera_origin) {
        cam.origin = *job.camera_origin;
        cam.up = job.camera_up;
        if (!job.camera_target_given) cam.target = prep->boundary->bounds().centre();
    }
    if (job.camera_target_given) cam.target = job.camera_target;
    cam.validate();
    prep->camera = cam;
    return prep;
}

}  // namespace jade
