// The fit at library level: a render of a known volume at a known k_s is the
// "photo"; the fit session, started from 0 on the same volume, must give that
// k_s back (to the precision |ΔA| < 1 level allows).

#include "jade/core/display.h"
#include "jade/fit/display.h"
#include "jade/fit/fit_session.h"
#include "jade/geometry/mesh.h"
#include "jade/geometry/mesh_accel.h"
#include "jade/core/error.h"
#include "jade/render/media/grid.h"
#include "jade/render/renderer.h"
#include "support/fit_test_scene.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jade;

namespace {

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
    test::FitTestScene t(test::ramp_photo(60, 150, 30), 48);
    const Scene& scene = t.scene;
    const CameraParams& camera = t.camera;
    const MaterialVolume& volume = t.volume;
    RenderSettings settings;
    settings.spp = 64;

    // The "photo": the same volume at the true k_s, with twice the fit's
    // samples, so that its own noise moves A by far less than a level (from
    // a photo of 2048 samples the fit finds (0.621, 0.310, −0.043) against
    // (0.611, 0.263, −0.044): false position's point follows ΔA itself,
    // within the freedom |ΔA| < 1 leaves, where halving's followed its sign).
    const std::array<double, 3> truth{0.6, 0.3, -0.05};
    const float exposure = 4.f;
    FitOptions make;
    make.width = camera.width;
    make.exposure = exposure;
    const Photo dummy = test::ramp_photo(60, 150, 30);
    RenderSettings photo_settings;
    photo_settings.seed = test::kPhotoSeed;
    const FitSession maker(volume, scene, camera, photo_settings, dummy, make);
    const Photo photo = photo_of(maker.render_at(truth, {1.0, 1.0, 1.0}, 512).film, exposure);

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

    // dA/dk_s at the fitted k_s (the brightness check's and the contrast
    // steps' first slope) against a centred difference of two renders
    // 0.05 either side, made here: within 15 %, though the search's
    // renders lie up to a unit and more away on one side.
    std::array<double, 3> lo = out.ks, hi = out.ks;
    for (int c = 0; c < 3; ++c) lo[c] -= 0.05, hi[c] += 0.05;
    const std::array<double, 3> a_lo = display_statistics(session.render_at(lo, {1.0, 1.0, 1.0}, 256).film, exposure).a;
    const std::array<double, 3> a_hi = display_statistics(session.render_at(hi, {1.0, 1.0, 1.0}, 256).film, exposure).a;
    for (int c = 0; c < 3; ++c) {
        const double local = (a_hi[c] - a_lo[c]) / 0.1;
        INFO("channel " << c << ": the fit's slope " << out.brightness_slope[c] << ", centred " << local);
        CHECK(out.brightness_slope[c] == Approx(local).epsilon(0.15));
    }
}

TEST_CASE("fit session: fitted at a quarter of the size, the brightness check brings A at full size to the photo's",
          "[fitter][fit-session]") {
    // The "photo" is the volume at a known k_s and contrast 3 rendered at
    // 80²; the fit runs at 40², where a pixel averages 4 of the photo's and
    // A is higher (sRGB is concave): ΔA at 80² is −1.1 to −1.4 levels. The
    // check at 80² must foresee A there and correct k_s so that an 80²
    // render matches the photo.
    test::FitTestScene t(test::ramp_photo(60, 150, 30), 80);
    RenderSettings settings;
    const std::array<double, 3> truth{0.6, 0.3, 0.1}, contrast{3.0, 3.0, 3.0};
    const float exposure = 4.f;
    FitOptions make;
    make.width = t.camera.width;
    make.exposure = exposure;
    const Photo dummy = test::ramp_photo(60, 150, 30);
    RenderSettings photo_settings;
    photo_settings.seed = test::kPhotoSeed;
    // At the full-size renders' 256 samples, so that the photo's A carries
    // the same noise bias (through the concave sRGB curve) as theirs.
    const Photo photo =
        photo_of(FitSession(t.volume, t.scene, t.camera, photo_settings, dummy, make).render_at(truth, contrast, 256).film,
                 exposure);
    const FitSession full(t.volume, t.scene, t.camera, settings, dummy, make);
    const RgbHistogram photo_histogram = RgbHistogram::of(photo.foreground_levels());
    // ΔA of an 80² render at k_s, and its standard error.
    auto delta_at_full_size = [&](const std::array<double, 3>& ks, std::array<double, 3>& sigma) {
        const DisplayStatistics st = display_statistics(full.render_at(ks, contrast, 256).film, exposure);
        std::array<double, 3> d{};
        for (int c = 0; c < 3; ++c) d[c] = st.a[c] - photo_histogram.mean(c), sigma[c] = st.a_sigma[c];
        return d;
    };

    FitOptions options = make;
    options.width = 40;
    options.ks_start = std::array<double, 3>{0.0, 0.0, 0.0};
    options.contrast_start = contrast;
    options.method = FitMethod::Bisect;
    options.spp = 256;
    FitSession session(t.volume, t.scene, t.camera, settings, photo, options);
    const FitOutcome out = session.run();
    REQUIRE(out.converged);
    const FitSession::FinalBrightness check = session.final_brightness(64);
    // The k_s-only fit renders nothing at 80²: the check renders both sizes.
    CHECK_FALSE(check.from_fit);
    CHECK(check.spp == 64);
    std::array<double, 3> sigma{}, sigma_after{};
    const std::array<double, 3> before = delta_at_full_size(out.ks, sigma);
    const std::array<double, 3> after = delta_at_full_size(check.ks, sigma_after);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": size change " << check.size_change[c] << ", dA expected " << check.delta[c]
                        << ", at 256 spp " << before[c] << " +- " << sigma[c] << "; after the correction " << after[c]
                        << " +- " << sigma_after[c]);
        // The check's own noise at 64 spp (its standard error here is below
        // 0.2 levels) and the noise bias left at 64 against 256 spp: 0.6.
        CHECK(check.delta[c] == Approx(before[c]).margin(0.6));
        // A channel the check foresees off by 0.4 of the tolerance or more
        // is moved to within that; one it foresees nearer is left. Either
        // then lies within 0.4 levels and the foresight's own error (0.6,
        // above) of the photo.
        CHECK(std::abs(after[c]) < 0.4 + 0.6);
    }
    CHECK_FALSE(check.from_final_render);

    // Given the final render's first 64 samples (the volume at the fitted
    // k_s through its own medium, before the environment, as the pipeline
    // renders it), the object alone, the check reads A at full size from
    // them instead of a render of its own: the same foresight, within the
    // same margin.
    MaterialVolume fitted = t.volume;
    fitted.optics.ks = out.ks;
    fitted.optics.contrast = contrast;
    fitted.optics.density_scale = out.density_scale;
    const MaterialVolumeMedium medium(fitted, fitted.cube);
    Scene final_scene = t.scene;
    final_scene.medium = &medium;
    RenderSettings final_settings = settings;
    final_settings.spp = 256;
    REQUIRE_FALSE(final_settings.backdrop.transparent);
    ProgressiveRender final_render(final_scene, PinholeCamera(t.camera), final_settings);
    Film object_alone(t.camera.width, t.camera.height);
    final_render.run_to(64, nullptr, nullptr, &object_alone);
    const FitSession::FinalBrightness read = session.final_brightness(64, &object_alone);
    CHECK(read.from_final_render);
    CHECK_FALSE(read.from_fit);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": dA expected from the final render's first samples " << read.delta[c]
                        << ", at 256 spp " << before[c]);
        CHECK(read.delta[c] == Approx(before[c]).margin(0.6));
    }
    final_render.run_to(128);
    CHECK_THROWS_AS(session.final_brightness(64, &final_render.result().film), Error);

    const bool foreseen_off = std::max({std::abs(check.delta[0]), std::abs(check.delta[1]), std::abs(check.delta[2])}) >= 0.4;
    CHECK((check.renders >= 1) == foreseen_off);
    CHECK(check.renders <= 3);
    // The size matters here: without the check, a channel is off by more than the tolerance.
    CHECK(std::max({std::abs(before[0]), std::abs(before[1]), std::abs(before[2])}) > 1.0);
}

TEST_CASE("the sharpening a fit asks for: by how far it raised the density scale", "[fitter][fit-session]") {
    FitOutcome fit;
    fit.converged = true;
    fit.density_scale_start = 20.0;
    fit.density_scale_max = 160.0;
    fit.density_scale = 71.0;  // Onyx010 on the cow
    CHECK(sharpening_for(fit).amount == kSharperStone);
    fit.density_scale = 160.0;  // the demo: at the ceiling
    CHECK(sharpening_for(fit).amount == kDefaultSharpen);
    CHECK_THAT(sharpening_for(fit).why, Catch::Contains("ceiling"));
    fit.density_scale = 150.0;  // short of it by less than a step of density
    CHECK(sharpening_for(fit).amount == kDefaultSharpen);
    fit.density_scale = 20.0;  // the marbles: at the volume's own
    CHECK(sharpening_for(fit).amount == 0.0);
    CHECK_THAT(sharpening_for(fit).why, Catch::Contains("the volume's own"));
    fit.density_scale = 71.0;
    fit.converged = false;
    CHECK(sharpening_for(fit).amount == 0.0);
    CHECK_THAT(sharpening_for(fit).why, Catch::Contains("did not converge"));
    // Stopped at the ceiling (FitOptions::stop_at_density_ceiling): not
    // converged, and the sharpening the ceiling asks for.
    fit.density_scale = 160.0;
    fit.stopped_at_density_ceiling = true;
    CHECK(sharpening_for(fit).amount == kDefaultSharpen);
    CHECK_THAT(sharpening_for(fit).why, Catch::Contains("ceiling"));
    CHECK(stopped_for_sharper_stone(fit));
    // Stopped at its first rise short of the ceiling
    // (FitOptions::stop_at_first_rise): the sharper stone.
    fit.stopped_at_density_ceiling = false;
    fit.stopped_at_first_rise = true;
    fit.density_scale = 58.6;
    CHECK(sharpening_for(fit).amount == kSharperStone);
    CHECK_THAT(sharpening_for(fit).why, Catch::Contains("first rise"));
    CHECK(stopped_for_sharper_stone(fit));
    fit.stopped_at_first_rise = false;
    CHECK_FALSE(stopped_for_sharper_stone(fit));
    CHECK(at_density_ceiling(160.0, 160.0));
    CHECK(at_density_ceiling(150.0, 160.0));
    CHECK_FALSE(at_density_ceiling(140.0, 160.0));
}

TEST_CASE("a fit started from another's outcome: only under --fit contrast", "[fitter][fit-session]") {
    FitOptions options;
    options.start = FitStart{};
    CHECK_NOTHROW(options.validate());
    options.method = FitMethod::Bisect;
    CHECK_THROWS_WITH(options.validate(), Catch::Contains("--fit contrast"));
}
