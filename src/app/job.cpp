#include "jade/app/job.h"

#include "jade/core/error.h"
#include "jade/core/parse.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace jade {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json vec(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

// A path as the document stores it: relative to the document's folder.
std::string stored_path(const std::string& path, const std::string& base) {
    if (path.empty() || path == "auto") return path;
    std::error_code ec;
    const fs::path rel = fs::proximate(fs::absolute(path, ec), fs::absolute(base, ec), ec);
    return ec ? path : rel.generic_string();
}

// A path read from the document: relative ones are relative to its folder.
std::string resolved_path(const std::string& path, const fs::path& base) {
    if (path.empty() || path == "auto" || fs::path(path).is_absolute()) return path;
    return (base / path).lexically_normal().string();
}

// The environment is a colour or an image file; only a file is a path.
bool is_colour(const std::string& text) {
    glm::vec3 v;
    return parse_vec3(text, v);
}

// Reads key `key` of object `o` into `out` when present; a value of the wrong
// type is an error naming the file and the key.
template <typename T>
void read(const json& o, const char* key, T& out, const std::string& file, const std::string& where) {
    if (!o.contains(key)) return;
    try {
        out = o.at(key).get<T>();
    } catch (const json::exception&) {
        fail_file(file, "'" + where + "." + key + "' has the wrong type");
    }
}

void read_vec(const json& o, const char* key, glm::vec3& out, const std::string& file,
              const std::string& where) {
    std::array<float, 3> a{out.x, out.y, out.z};
    read(o, key, a, file, where);
    out = glm::vec3(a[0], a[1], a[2]);
}

// settings.light_nee: an estimator's name, or true / false as older jobs
// stored it.
void read_light_nee(const json& settings, LightThroughBoundary& out, const std::string& file) {
    if (!settings.contains("light_nee")) return;
    const json& v = settings.at("light_nee");
    try {
        out = parse_light_through_boundary(v.is_boolean() ? (v.get<bool>() ? "true" : "false")
                                                          : v.get<std::string>());
    } catch (const json::exception&) {
        fail_file(file, "'settings.light_nee' has the wrong type");
    } catch (const Error& e) {
        fail_file(file, "'settings.light_nee': " + std::string(e.what()));
    }
}

// settings.light_chain: "auto", 1 or 2 (a number or its text).
void read_light_chain(const json& settings, LightChain& out, const std::string& file) {
    if (!settings.contains("light_chain")) return;
    const json& v = settings.at("light_chain");
    if (!v.is_string() && !v.is_number_integer()) fail_file(file, "'settings.light_chain' has the wrong type");
    try {
        out = parse_light_chain(v.is_string() ? v.get<std::string>() : std::to_string(v.get<int>()));
    } catch (const Error& e) {
        fail_file(file, "'settings.light_chain': " + std::string(e.what()));
    }
}

}  // namespace

std::string sibling_path(const std::string& out, const std::string& suffix) {
    const fs::path p(out);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

std::string job_json(const RenderJob& job, const std::string& base_dir) {
    json medium = {{"volume", stored_path(job.volume, base_dir)},
                   {"vdb_density_scale", job.density.scale},
                   {"vdb_albedo", vec(job.density.albedo)}};
    if (job.ks) medium["ks"] = *job.ks;
    if (job.contrast) medium["contrast"] = *job.contrast;
    if (job.sigma_s) medium["sigma_s"] = vec(*job.sigma_s);
    if (job.sigma_a) medium["sigma_a"] = vec(*job.sigma_a);
    json camera = {{"file", stored_path(job.camera_file, base_dir)}, {"up", vec(job.camera_up)},
                   {"fov_degrees", job.fov_degrees}, {"width", job.width}, {"height", job.height}};
    if (job.camera_origin) camera["origin"] = vec(*job.camera_origin);
    if (job.camera_target_given) camera["target"] = vec(job.camera_target);
    json scene = {{"mesh", stored_path(job.mesh, base_dir)}, {"flat_normals", job.flat_normals},
                  {"allow_open", job.allow_open}, {"boundary", to_string(job.interface.mode)},
                  {"ior", job.interface.ior}, {"specular", job.interface.specular}, {"g", job.g}};
    if (job.sphere) scene["sphere"] = *job.sphere;
    const json j = {
        {"scene", scene},
        {"medium", medium},
        {"camera", camera},
        {"lights", {{"direction", vec(job.light_direction)}, {"irradiance", job.light_irradiance},
                    {"radius_degrees", job.light_radius_degrees},
                    {"file", stored_path(job.light_file, base_dir)},
                    {"file_resolved", !job.light_file.empty() && job.light_file_resolved},
                    {"environment", is_colour(job.environment) ? job.environment
                                                               : stored_path(job.environment, base_dir)},
                    {"environment_scale", job.environment_scale},
                    {"background", stored_path(job.background, base_dir)},
                    {"transparent", job.transparent}}},
        {"settings", {{"spp", job.settings.spp}, {"time_limit", job.settings.time_limit},
                      {"target_error", job.settings.target_error}, {"seed", job.settings.seed},
                      {"max_depth", job.settings.integrator.max_depth},
                      {"light_nee", to_string(job.settings.integrator.light_through_boundary)},
                      {"light_chain", to_string(job.settings.integrator.light_chain)},
                      {"light_guide", job.settings.integrator.light_guide},
                      {"env_share", job.settings.integrator.environment_share},
                      {"light_share", job.settings.integrator.light_share}}},
        {"outputs", {{"out", stored_path(job.out, base_dir)}, {"png", stored_path(job.png, base_dir)},
                     {"convergence", stored_path(job.convergence, base_dir)},
                     {"reference", stored_path(job.reference, base_dir)}, {"exposure", job.exposure}}}};
    return j.dump(2);
}

namespace {

void read_scene_and_medium(const json& j, RenderJob& job, const std::string& file) {
    const json scene = j.value("scene", json::object()), medium = j.value("medium", json::object());
    read(scene, "mesh", job.mesh, file, "scene");
    if (scene.contains("sphere")) {
        std::array<float, 4> s{};
        read(scene, "sphere", s, file, "scene");
        job.sphere = s;
    }
    read(scene, "flat_normals", job.flat_normals, file, "scene");
    read(scene, "allow_open", job.allow_open, file, "scene");
    std::string mode = to_string(job.interface.mode);
    read(scene, "boundary", mode, file, "scene");
    job.interface.mode = parse_boundary_mode(mode);
    read(scene, "ior", job.interface.ior, file, "scene");
    read(scene, "specular", job.interface.specular, file, "scene");
    read(scene, "g", job.g, file, "scene");
    read(medium, "volume", job.volume, file, "medium");
    read(medium, "vdb_density_scale", job.density.scale, file, "medium");
    read_vec(medium, "vdb_albedo", job.density.albedo, file, "medium");
    for (auto [key, target] : {std::pair{"ks", &job.ks}, std::pair{"contrast", &job.contrast}})
        if (medium.contains(key)) {
            std::array<float, 3> v{};
            read(medium, key, v, file, "medium");
            *target = v;
        }
    for (auto [key, target] : {std::pair{"sigma_s", &job.sigma_s}, std::pair{"sigma_a", &job.sigma_a}})
        if (medium.contains(key)) {
            glm::vec3 v(0.f);
            read_vec(medium, key, v, file, "medium");
            *target = v;
        }
}

void read_camera_lights_settings(const json& j, RenderJob& job, const std::string& file) {
    const json camera = j.value("camera", json::object()), lights = j.value("lights", json::object()),
               settings = j.value("settings", json::object()), outputs = j.value("outputs", json::object());
    read(camera, "file", job.camera_file, file, "camera");
    if (camera.contains("origin")) {
        glm::vec3 o(0.f);
        read_vec(camera, "origin", o, file, "camera");
        job.camera_origin = o;
    }
    if (camera.contains("target")) {
        read_vec(camera, "target", job.camera_target, file, "camera");
        job.camera_target_given = true;
    }
    read_vec(camera, "up", job.camera_up, file, "camera");
    read(camera, "fov_degrees", job.fov_degrees, file, "camera");
    read(camera, "width", job.width, file, "camera");
    read(camera, "height", job.height, file, "camera");
    read_vec(lights, "direction", job.light_direction, file, "lights");
    read(lights, "irradiance", job.light_irradiance, file, "lights");
    read(lights, "radius_degrees", job.light_radius_degrees, file, "lights");
    read(lights, "file", job.light_file, file, "lights");
    read(lights, "file_resolved", job.light_file_resolved, file, "lights");
    read(lights, "environment", job.environment, file, "lights");
    read(lights, "environment_scale", job.environment_scale, file, "lights");
    read(lights, "background", job.background, file, "lights");
    read(lights, "transparent", job.transparent, file, "lights");
    read(settings, "spp", job.settings.spp, file, "settings");
    read(settings, "time_limit", job.settings.time_limit, file, "settings");
    read(settings, "target_error", job.settings.target_error, file, "settings");
    read(settings, "seed", job.settings.seed, file, "settings");
    read(settings, "max_depth", job.settings.integrator.max_depth, file, "settings");
    read_light_nee(settings, job.settings.integrator.light_through_boundary, file);
    read_light_chain(settings, job.settings.integrator.light_chain, file);
    read(settings, "light_guide", job.settings.integrator.light_guide, file, "settings");
    read(settings, "env_share", job.settings.integrator.environment_share, file, "settings");
    read(settings, "light_share", job.settings.integrator.light_share, file, "settings");
    read(outputs, "out", job.out, file, "outputs");
    read(outputs, "png", job.png, file, "outputs");
    read(outputs, "convergence", job.convergence, file, "outputs");
    read(outputs, "reference", job.reference, file, "outputs");
    read(outputs, "exposure", job.exposure, file, "outputs");
}

}  // namespace

RenderJob parse_job(const std::string& text, const std::string& origin, const std::string& base_dir) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        fail_file(origin, std::string("not valid JSON: ") + e.what());
    }
    if (j.is_object() && j.contains("job")) j = j["job"];
    if (!j.is_object() || !j.contains("scene")) fail_file(origin, "holds no render job ('scene' is missing)");
    RenderJob job;
    read_scene_and_medium(j, job, origin);
    read_camera_lights_settings(j, job, origin);
    const fs::path base(base_dir);
    for (std::string* p : {&job.mesh, &job.volume, &job.camera_file, &job.light_file, &job.background, &job.out,
                           &job.png, &job.convergence, &job.reference})
        *p = resolved_path(*p, base);
    if (!is_colour(job.environment)) job.environment = resolved_path(job.environment, base);
    return job;
}

RenderJob load_job(const std::string& path) {
    std::ifstream in(path);
    if (!in) fail_file(path, "no such file, or it cannot be read");
    std::stringstream text;
    text << in.rdbuf();
    return parse_job(text.str(), path, fs::path(path).parent_path().string());
}

}  // namespace jade
