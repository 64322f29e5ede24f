#pragma once
// The small scene the fit's round-trip tests share: a 16³ material volume in
// an icosphere of radius 1, lit by a 20° disc light over a dim environment,
// seen from 4 units away. The mesh and its accelerator live in the object,
// so the scene's pointers stay valid as long as it does.

#include "jade/fit/fit_session.h"
#include "jade/geometry/mesh.h"
#include "jade/geometry/mesh_accel.h"

#include <cstdint>

namespace jade::test {

// A stone-like photo to build the volume from: a ramp of warm colours from
// level `low` over `span` levels.
inline Photo ramp_photo(int low, int span, int tint) {
    Photo p;
    p.width = p.height = 32;
    for (int i = 0; i < 32 * 32; ++i) {
        const int l = low + (i * span) / (32 * 32);
        p.levels.push_back({std::uint8_t(l + tint), std::uint8_t(l), std::uint8_t(l - tint)});
    }
    p.foreground.assign(p.levels.size(), 1);
    return p;
}

// The seed of the renders that make a round trip's "photo": not the fit's
// (RenderSettings' default), so that the fit does not meet the photo's own
// noise again through common random numbers.
inline constexpr std::uint64_t kPhotoSeed = 7;

struct FitTestScene {
    TriangleMesh mesh = icosphere(3, 1.f);
    MeshAccel accel{mesh};
    Scene scene;
    CameraParams camera;
    MaterialVolume volume;

    FitTestScene(const Photo& stone, int width) {
        scene.boundary = &accel;
        scene.fit_ray_epsilon();
        scene.light = DirectionalLight({0.3f, 0.5f, 1.f}, 3.f, 20.f);
        scene.environment = Environment(Spectrum(0.02f));
        camera.origin = {0.f, 0.f, 4.f};
        camera.width = camera.height = width;
        NoiseParams noise;
        noise.resolution = 16;
        volume = build_material_volume(stone, noise, MatchMode::Joint, OpticalParams{});
        volume.cube = bounding_cube(mesh);
    }
    FitTestScene(const FitTestScene&) = delete;
    FitTestScene& operator=(const FitTestScene&) = delete;
};

}  // namespace jade::test
