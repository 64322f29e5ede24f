// The fit at library level: a render of a known volume at a known k_s is the
// "photo"; the fit session, started from 0 on the same volume, must give that
// k_s back (to the precision |ΔA| < 1 level allows).

#include "jade/core/display.h"
#include "jade/fit/fit_session.h"
#include "jade/geometry/mesh.h"
#include "jade/geometry/mesh_accel.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jade;

namespace {

// A stone-like photo to build the volume from: a ramp of warm colours.
Photo ramp_photo() {
    Photo p;
    p.width = p.height = 32;
    for (int i = 0; i < 32 * 32; ++i) {
        const int l = 60 + (i * 150) / (32 * 32);
        p.levels.push_back({std::uint8_t(l + 30), std::uint8_t(l), std::uint8_t(l - 30)});
    }
    p.foreground.assign(p.levels.size(), 1);
    return p;
}

// The render's object pixels as a photo (display levels at `exposure`).
Photo photo_of(const Film& film, float exposure) {
    Photo p;
    p.width = film.width();
    p.height = film.height();
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const float cov = film.coverage(x, y);
            const Spectrum m = film.mean(x, y) * (exposure / std::max(cov, 1e-6f));
            p.levels.push_back({display_level(m.x), display_level(m.y), display_level(m.z)});
            p.foreground.push_back(is_object_pixel(cov) ? 1 : 0);
        }
    return p;
}

}  // namespace

TEST_CASE("fit session: a render at a known k_s, fitted from 0, gives that k_s back", "[fitter][fit-session]") {
    const TriangleMesh mesh = icosphere(3, 1.f);
    const MeshAccel accel(mesh);
    Scene scene;
    scene.boundary = &accel;
    scene.fit_ray_epsilon();
    scene.light = DirectionalLight({0.3f, 0.5f, 1.f}, 3.f, 20.f);
    scene.environment = Environment(Spectrum(0.02f));
    CameraParams camera;
    camera.origin = {0.f, 0.f, 4.f};
    camera.width = camera.height = 48;

    NoiseParams noise;
    noise.resolution = 16;
    MaterialVolume volume = build_material_volume(ramp_photo(), noise, MatchMode::Joint, OpticalParams{});
    volume.cube = bounding_cube(mesh);
    RenderSettings settings;
    settings.spp = 64;

    // The "photo": the same volume at the true k_s, with many samples so that
    // its own noise moves A by far less than a level.
    const std::array<double, 3> truth{0.6, 0.3, -0.05};
    const float exposure = 4.f;
    FitOptions make;
    make.width = camera.width;
    make.exposure = exposure;
    const Photo dummy = ramp_photo();
    const FitSession maker(volume, scene, camera, settings, dummy, make);
    const Photo photo = photo_of(maker.render_at(truth, {1.0, 1.0, 1.0}, 2048).film, exposure);

    FitOptions options = make;
    options.ks_start = std::array<double, 3>{0.0, 0.0, 0.0};
    options.method = FitMethod::Bisect;  // the k_s-only fit; the contrast fit has its own test
    options.spp = 256;
    FitSession session(volume, scene, camera, settings, photo, options);
    const FitOutcome out = session.run();
    INFO("k_s " << out.ks[0] << ", " << out.ks[1] << ", " << out.ks[2] << " in " << out.records.size() << " renders");
    REQUIRE(out.converged);
    CHECK(out.records.size() <= 12);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(out.ks[c] - truth[c]) < 0.12);
}
