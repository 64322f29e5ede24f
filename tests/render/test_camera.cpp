// Pinhole camera: the horizontal field of view and the film convention of the
// reference renders.

#include "jade/render/camera.h"

#include "support/test_util.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <fstream>

using namespace jade;

TEST_CASE("film coordinates follow the reference convention, fov horizontal", "[camera]") {
    CameraParams p;  // origin (0,0,4) looking at the origin, 40 degrees
    p.width = 200;
    p.height = 100;
    const PinholeCamera cam(p);
    const float t = std::tan(20.f * 3.14159265f / 180.f);
    const glm::vec3 centre = cam.direction(0.5f, 0.5f);
    CHECK(glm::length(centre - glm::vec3(0, 0, -1)) < 1e-6f);
    // Right edge, middle row: 20 degrees to the right (+x).
    const glm::vec3 right = cam.direction(1.f, 0.5f);
    CHECK(std::atan2(right.x, -right.z) * 180.f / 3.14159265f == Approx(20.f));
    // Top edge: half the horizontal tangent for a 2:1 image, toward +y.
    const glm::vec3 top = cam.direction(0.5f, 0.f);
    CHECK(top.y / -top.z == Approx(t * 0.5f));
    // A corner of a square image: forward + tan20 * (right + up).
    p.width = p.height = 64;
    const glm::vec3 corner = PinholeCamera(p).direction(0.f, 0.f);
    CHECK(glm::length(corner - glm::normalize(glm::vec3(-t, t, -1.f))) < 1e-6f);
}

TEST_CASE("framing puts the whole mesh in view from the upper front", "[camera]") {
    Bounds3 b;
    b.extend({-3, 0, -1});
    b.extend({1, 5, 2});
    const CameraParams p = frame_mesh(b, 320, 240);
    CHECK(p.origin.y > p.target.y);  // above
    CHECK(p.origin.z > p.target.z);  // in front (+z)
    const PinholeCamera cam(p);
    const glm::vec3 fwd = glm::normalize(p.target - p.origin);
    const glm::vec3 right = glm::normalize(glm::cross(fwd, p.up));
    const glm::vec3 up = glm::cross(right, fwd);
    const float tx = std::tan(20.f * 3.14159265f / 180.f), ty = tx * 240.f / 320.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                          (i & 4) ? b.max.z : b.min.z);
        const glm::vec3 v = c - p.origin;
        const float z = glm::dot(v, fwd);
        CHECK(std::abs(glm::dot(v, right) / z) < tx);
        CHECK(std::abs(glm::dot(v, up) / z) < ty);
    }
}

TEST_CASE("impossible cameras are rejected", "[camera]") {
    CameraParams p;
    p.fov_degrees = 180.f;
    CHECK_THROWS(p.validate());
    p = CameraParams{};
    p.up = glm::vec3(0, 0, 1);  // parallel to the view
    CHECK_THROWS(p.validate());
    p = CameraParams{};
    p.target = p.origin;
    CHECK_THROWS(p.validate());
}

TEST_CASE("a glTF file's camera: node transform, -z view, vertical fov made horizontal", "[camera]") {
    jade_test::TempDir dir;
    const std::string path = dir.file("cam.gltf");
    {
        // A camera node under a parent that translates by (1, 2, 3) and turns
        // 90 degrees about +y (quaternion (0, sin 45°, 0, cos 45°)): it then
        // looks along -x.
        std::ofstream out(path);
        out << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"translation": [1, 2, 3], "rotation": [0, 0.70710678, 0, 0.70710678], "children": [1]},
            {"camera": 0}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}]})";
    }
    const FileCamera c = load_gltf_camera(path);
    CHECK(c.origin.x == Approx(1.f));
    CHECK(c.origin.y == Approx(2.f));
    CHECK(c.origin.z == Approx(3.f));
    CHECK(c.forward.x == Approx(-1.f).margin(1e-6));
    CHECK(c.forward.z == Approx(0.f).margin(1e-6));
    CHECK(c.up.y == Approx(1.f).margin(1e-6));
    const CameraParams p = camera_from_file(c, 200, 100);
    // tan(hfov / 2) = tan(yfov / 2) * aspect.
    CHECK(std::tan(0.5 * p.fov_degrees * 3.14159265358979 / 180) == Approx(std::tan(0.25) * 2.0).epsilon(1e-5));
    const PinholeCamera cam(p);
    const glm::vec3 centre = cam.direction(0.5f, 0.5f);
    CHECK(centre.x == Approx(-1.f).margin(1e-5));
    // The top edge's centre is yfov / 2 above the view direction.
    CHECK(std::asin(double(cam.direction(0.5f, 0.f).y)) == Approx(0.25).epsilon(1e-4));

    CHECK_THROWS_WITH(load_gltf_camera(dir.file("none.glb")), Catch::Contains("none.glb"));
    CHECK_THROWS_WITH(load_gltf_camera(JADE_DATA_DIR "/meshes/greek-vase-01.glb"),
                      Catch::Contains("no perspective camera"));
}

TEST_CASE("a glTF file's directional light (KHR_lights_punctual): node transform, +z toward it, intensity",
          "[camera]") {
    jade_test::TempDir dir;
    const std::string path = dir.file("sun.gltf");
    {
        // A point light first (skipped), then a directional light on a node
        // turned -90 degrees about +x (quaternion (-sin 45°, 0, 0, cos 45°)):
        // it shines along -y, so the light is toward +y.
        std::ofstream out(path);
        out << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [
      {"type": "point", "intensity": 100},
      {"type": "directional", "name": "Sun", "intensity": 4, "color": [1, 0.5, 0.75]}]}},
  "nodes": [{"extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"rotation": [-0.70710678, 0, 0, 0.70710678], "extensions": {"KHR_lights_punctual": {"light": 1}}}]})";
    }
    const FileLight light = load_gltf_directional_light(path);
    CHECK(light.name == "Sun");
    CHECK(light.toward.x == Approx(0.f).margin(1e-6));
    CHECK(light.toward.y == Approx(1.f).margin(1e-6));
    CHECK(light.toward.z == Approx(0.f).margin(1e-6));
    CHECK(light.irradiance == Approx(4.f * 0.75f));  // intensity × the colour's mean
    CHECK(light.coloured);
    CHECK_THROWS_WITH(load_gltf_directional_light(JADE_DATA_DIR "/meshes/greek-vase-01.glb"),
                      Catch::Contains("holds no directional light"));
    CHECK_THROWS_WITH(load_gltf_directional_light(JADE_DATA_DIR "/meshes/spot-cow.obj"),
                      Catch::Contains(".gltf or .glb only"));
}
