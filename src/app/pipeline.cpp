#include "jade/app/pipeline.h"

#include "jade/io/atomic_file.h"
#include "jade/fit/compare.h"
#include "jade/core/error.h"
#include "jade/io/image_io.h"
#include "jade/render/media/grid.h"
#include "jade/volume/photo.h"
#include "jade/core/progress.h"
#include "jade/core/timing.h"
#include "jade/io/vdb_io.h"

#include <OpenImageIO/oiioversion.h>
#include <embree3/rtcore_config.h>
#include <nlohmann/json.hpp>
#include <oneapi/tbb/version.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace jade {

namespace {

namespace fs = std::filesystem;

// The render job's camera at another resolution, same aspect and framing.
CameraParams at_resolution(CameraParams cam, int width) {
    const double aspect = double(cam.height) / cam.width;
    cam.width = width;
    cam.height = std::max(1, int(std::lround(width * aspect)));
    return cam;
}

void write_text(const std::string& path, const std::string& text) {
    AtomicFile file(path);
    {
        std::ofstream out(file.temp_path());
        out << text;
        if (!out) fail_file(path, "cannot write");
    }
    file.commit();
}

std::string fit_csv(const std::vector<FitRecord>& rows) {
    std::string s = "iteration,seconds,spp";
    const char* ch[3] = {"r", "g", "b"};
    for (const char* name : {"ks", "A_photo", "A_render", "A_sigma", "dA", "D"})
        for (const char* c : ch) s += std::string(",") + name + "_" + c;
    s += "\n";
    char buf[64];
    for (const FitRecord& r : rows) {
        std::snprintf(buf, sizeof buf, "%d,%.3f,%d", r.iteration, r.seconds, r.spp);
        s += buf;
        for (const auto* arr : {&r.ks, &r.a_photo, &r.a_render, &r.a_sigma, &r.delta, &r.distance})
            for (double v : *arr) {
                std::snprintf(buf, sizeof buf, ",%.6g", v);
                s += buf;
            }
        s += "\n";
    }
    return s;
}

}  // namespace

std::string default_out_dir(const std::string& photo) {
    return fs::path(photo).stem().string() + "-jaderender";
}

PipelineResult run_pipeline(const PipelineOptions& o) {
    const Stopwatch total;
    PipelineResult res;
    o.noise.validate();
    o.optics.validate();
    o.render.settings.validate();
    if (o.fit_max_renders < 1) throw Error("--fit-max-renders must be at least 1");
    if (o.fit_max_renders < 2 && (o.fit == FitMethod::Bisect || o.exposure == 0.f))
        throw Error("--fit-max-renders must be at least 2: the fit starts with renders at both k_s bounds");
    if (!(o.fit_noise > 0)) throw Error("--fit-noise must be positive");
    if (!(o.fit_error > 0)) throw Error("--fit-error must be positive");
    if (o.fit_spp_max < 16) throw Error("--fit-spp-max must be at least 16");
    if (!(o.exposure >= 0) || !std::isfinite(o.exposure))
        throw Error("--exposure must be positive (or 0: matched to the photo)");
    if (o.fit_width < 0 || o.fit_spp < 0) throw Error("--fit-width and --fit-spp must not be negative");
    res.out_dir = o.out_dir.empty() ? default_out_dir(o.photo) : o.out_dir;
    {
        const fs::path parent = fs::path(res.out_dir).parent_path();
        std::error_code ec;
        if (!parent.empty() && !fs::is_directory(parent, ec))
            fail_file(res.out_dir, "the folder '" + parent.string() + "' does not exist");
    }

    // Inputs.
    Stopwatch clock;
    const Photo photo = load_photo(o.photo, o.mask);
    const RgbHistogram photo_hist = RgbHistogram::of(photo.foreground_levels());
    const std::unique_ptr<PreparedScene> prep = prepare_scene(o.render);
    res.warnings = prep->warnings;
    res.seconds_photo = clock.seconds();

    // Material volume on the mesh's cube.
    clock = Stopwatch();
    MaterialVolume volume;
    {
        std::unique_ptr<Progress> bar;
        if (o.progress) bar = std::make_unique<Progress>("noise + colour matching", std::size_t(o.noise.resolution));
        if (o.volume.empty()) {
            volume = build_material_volume(photo, o.noise, o.match, o.optics, bar.get());
        } else {
            volume = read_material_vdb(o.volume);
        }
    }
    volume.cube = prep->cube;
    res.seconds_volume = clock.seconds();

    // k_s may go down until σ_s = v·d_s + k_s reaches 0 in the lowest voxel.
    FitLimits limits = o.limits;
    for (int c = 0; c < 3; ++c) {
        int lowest = 255;
        for (const Rgb8& lv : volume.levels) lowest = std::min(lowest, int(lv[c]));
        limits.k_min[c] = -(lowest / 256.0) * volume.optics.ds;
    }

    // Fitting renders: no background (the object's pixels are all that count),
    // a reduced image, the same random sequence every time, and one majorant
    // (that of k_s = k_max) for all of them, so that every render makes the
    // same tentative collisions and A(k_s) changes smoothly with k_s.
    clock = Stopwatch();
    Scene fit_scene = prep->scene;
    const int final_width = prep->camera.width;
    const PinholeCamera fit_camera(at_resolution(prep->camera, o.fit_width > 0 ? o.fit_width : std::max(32, final_width / 4)));
    RenderSettings fit_settings = o.render.settings;
    fit_settings.time_limit = 0;
    fit_settings.target_error = 0;
    fit_settings.reference = nullptr;
    fit_settings.backdrop = Backdrop{nullptr, true};
    int fit_spp = o.fit_spp;
    double fit_error_measured = 0.0;  // the first fitting render's estimated relative error
    const std::array<double, 3> ks_start = o.ks_start.value_or(volume.optics.ks);
    volume.optics.ks = {limits.k_max, limits.k_max, limits.k_max};
    const Spectrum shared_majorant = MaterialVolumeMedium(volume, volume.cube).majorant();

    FitDriver driver(o.fit, ks_start, limits);
    float exposure = o.exposure;
    auto render_at = [&](const std::array<double, 3>& ks, int spp) {
        volume.optics.ks = ks;
        const MaterialVolumeMedium medium(volume, volume.cube, shared_majorant);
        fit_scene.medium = &medium;
        fit_settings.spp = spp;
        return render(fit_scene, fit_camera, fit_settings);
    };
    std::unique_ptr<Progress> fit_bar;
    if (o.progress && o.fit != FitMethod::None)
        fit_bar = std::make_unique<Progress>("fitting k_s", std::size_t(o.fit_max_renders));
    // One fitting render at ks; the first chooses the sample count: doubled
    // from kFirstFitSpp until A's standard error is below fit_noise in every
    // channel (measured at the photo's mean luminance) and the estimated
    // per-pixel error below fit_error. The light's rare paths make both
    // estimates read low at a few samples, hence the start at 256.
    auto fitting_render = [&](const std::array<double, 3>& ks) {
        RenderResult r;
        if (fit_spp == 0) {
            constexpr int kFirstFitSpp = 256;
            for (int spp = std::min(kFirstFitSpp, o.fit_spp_max);; spp *= 2) {
                r = render_at(ks, spp);
                const DisplayStatistics st =
                    display_statistics(r.film, exposure > 0 ? exposure : matching_exposure(r.film, photo));
                if (st.pixels == 0)
                    throw Error("the object covers no pixel of the fitting render; check the camera");
                // A's own scatter is not enough: a speckled image can have a
                // steady mean histogram that is not the converged one's.
                const bool a_steady = std::max({st.a_sigma[0], st.a_sigma[1], st.a_sigma[2]}) <= o.fit_noise;
                const bool pixels_converged = r.passes.back().estimated_error <= o.fit_error;
                if ((a_steady && pixels_converged) || spp >= o.fit_spp_max) {
                    fit_spp = spp;
                    fit_error_measured = r.passes.back().estimated_error;
                    break;
                }
            }
        } else {
            r = render_at(ks, fit_spp);
        }
        if (fit_bar) fit_bar->advance();
        return r;
    };
    auto record = [&](const std::array<double, 3>& ks, const DisplayStatistics& st) {
        FitRecord rec;
        rec.iteration = int(res.fit.size());
        rec.seconds = clock.seconds();
        rec.spp = fit_spp;
        rec.ks = ks;
        for (int c = 0; c < 3; ++c) {
            rec.a_photo[c] = photo_hist.mean(c);
            rec.a_render[c] = st.a[c];
            rec.a_sigma[c] = st.a_sigma[c];
            rec.delta[c] = st.a[c] - photo_hist.mean(c);
            rec.distance[c] = histogram_distance(st.histogram, photo_hist, c);
        }
        res.fit.push_back(rec);
        return rec.delta;
    };

    if (o.fit == FitMethod::Bisect || (o.fit != FitMethod::None && exposure == 0.f)) {
        // Renders at both bounds: they bracket every reachable channel, and
        // they fix the exposure (when not given) in the middle of the range
        // where every channel can reach the photo.
        const std::array<double, 3> k_lo = limits.k_min;
        const std::array<double, 3> k_hi{limits.k_max, limits.k_max, limits.k_max};
        const RenderResult r_lo = fitting_render(k_lo);
        const RenderResult r_hi = fitting_render(k_hi);
        if (exposure == 0.f)
            exposure = float(exposure_in_reach(
                r_lo.film, r_hi.film, {photo_hist.mean(0), photo_hist.mean(1), photo_hist.mean(2)}));
        const std::array<double, 3> d_lo = record(k_lo, display_statistics(r_lo.film, exposure));
        const std::array<double, 3> d_hi = record(k_hi, display_statistics(r_hi.film, exposure));
        if (o.fit == FitMethod::Bisect) driver.observe_bounds(d_lo, d_hi);
    }
    while (o.fit != FitMethod::None && !driver.done() && int(res.fit.size()) < o.fit_max_renders) {
        const std::array<double, 3> ks = driver.k();
        const RenderResult r = fitting_render(ks);
        if (exposure == 0.f) exposure = matching_exposure(r.film, photo);
        driver.observe(record(ks, display_statistics(r.film, exposure)));
    }
    if (fit_bar) fit_bar->finish();
    res.seconds_fit = clock.seconds();
    if (o.fit == FitMethod::None && exposure == 0.f) {
        // Nothing fitted: still match the exposure, from one fitting render.
        const RenderResult r = render_at(ks_start, fit_spp > 0 ? fit_spp : 64);
        exposure = matching_exposure(r.film, photo);
    }
    res.exposure = exposure;

    res.converged = true;
    for (int c = 0; c < 3; ++c) {
        res.ks[c] = o.fit == FitMethod::None ? ks_start[c] : driver.best_k()[c];
        switch (driver.state(c)) {
        case ChannelState::Converged:
            res.channel_status[c] = o.fit == FitMethod::None ? "not fitted" : "converged";
            break;
        case ChannelState::Unreachable:
            res.channel_status[c] = driver.reason(c);
            res.converged = false;
            break;
        case ChannelState::Searching:
            res.channel_status[c] = std::string(c == 0 ? "red" : c == 1 ? "green" : "blue") +
                                    ": not converged within --fit-max-renders " +
                                    std::to_string(o.fit_max_renders) + " renders";
            res.converged = false;
            break;
        }
    }

    // Final render at full size, with the background.
    clock = Stopwatch();
    volume.optics.ks = res.ks;
    const MaterialVolumeMedium medium(volume, volume.cube);
    Scene final_scene = prep->scene;
    final_scene.medium = &medium;
    {
        std::unique_ptr<Progress> bar;
        if (o.progress)
            bar = std::make_unique<Progress>("final render", std::size_t(prep->camera.width) *
                                                                 prep->camera.height * o.render.settings.spp);
        RenderSettings final_settings = o.render.settings;
        final_settings.backdrop = prep->backdrop;
        res.final_render = render(final_scene, PinholeCamera(prep->camera), final_settings, bar.get());
    }
    res.seconds_render = clock.seconds();

    // Outputs, each whole or not at all.
    clock = Stopwatch();
    std::error_code ec;
    fs::create_directories(res.out_dir, ec);
    if (ec) fail_file(res.out_dir, "cannot create the output folder: " + ec.message());
    auto out = [&](const char* name) { return (fs::path(res.out_dir) / name).string(); };
    write_material_vdb(out("volume.vdb"), volume);
    res.written.push_back(out("volume.vdb"));
    write_film(res.final_render.film, out("render.exr"), out("render.png"), prep->backdrop.transparent, exposure);
    res.written.push_back(out("render.exr"));
    res.written.push_back(out("render.png"));
    write_text(out("fit.csv"), fit_csv(res.fit));
    res.written.push_back(out("fit.csv"));
    write_convergence_csv(out("convergence.csv"), res.final_render.passes);
    res.written.push_back(out("convergence.csv"));
    const DisplayStatistics final_stats = display_statistics(res.final_render.film, exposure);
    const RgbImage8 cmp = compare_image(photo, res.final_render.film, exposure, photo_hist, final_stats.histogram);
    write_image_u8(out("compare.png"), cmp.width, cmp.height, 3, cmp.pixels);
    res.written.push_back(out("compare.png"));
    res.seconds_write = clock.seconds();
    res.seconds_total = total.seconds();

    using nlohmann::json;
    const PassRecord& last = res.final_render.passes.back();
    json j;
    j["versions"] = {{"jaderender", JADE_VERSION},      {"openvdb", openvdb_version()},
                     {"openimageio", OIIO_VERSION_STRING}, {"embree", RTC_VERSION_STRING},
                     {"tbb", TBB_VERSION_STRING}};
    j["inputs"] = {{"photo", o.photo}, {"mask", o.mask}, {"mesh", o.render.mesh},
                   {"foreground_pixels", photo.foreground_count()}};
    j["volume"] = {{"from", o.volume.empty() ? "built from the photo" : o.volume},
                   {"resolution", volume.resolution}, {"octaves", volume.noise.octaves},
                   {"k", volume.noise.k}, {"seed", volume.noise.seed}, {"match", to_string(volume.match)},
                   {"ds", volume.optics.ds}, {"da", volume.optics.da},
                   {"density_scale", volume.optics.density_scale},
                   {"cube_min", volume.cube.min}, {"cube_side", volume.cube.side}};
    j["fit"] = {{"method", to_string(o.fit)}, {"renders", res.fit.size()}, {"max_renders", o.fit_max_renders},
                {"spp", res.fit.empty() ? 0 : res.fit.front().spp}, {"width", fit_camera.width()},
                {"height", fit_camera.height()}, {"noise_target", o.fit_noise}, {"error_target", o.fit_error},
                {"estimated_relative_error", fit_error_measured}, {"exposure", exposure},
                {"exposure_matched", o.exposure == 0.f},
                {"tolerance", limits.tolerance}, {"step", limits.step}, {"ks_start", ks_start},
                {"ks_min", limits.k_min}, {"ks_max", limits.k_max}, {"ks", res.ks},
                {"converged", res.converged}, {"channel_status", res.channel_status}};
    if (!res.fit.empty()) {
        // The fitting render at the chosen k_s (the best per channel may come from different renders).
        std::array<double, 3> delta{}, dist{};
        for (int c = 0; c < 3; ++c) {
            double best = 1e300;
            for (const FitRecord& r : res.fit)
                if (r.ks[c] == res.ks[c] && std::abs(r.delta[c]) < best) {
                    best = std::abs(r.delta[c]);
                    delta[c] = r.delta[c];
                    dist[c] = r.distance[c];
                }
        }
        j["fit"]["final_delta_A"] = delta;
        j["fit"]["final_D"] = dist;
    }
    j["final_render"] = {{"width", prep->camera.width}, {"height", prep->camera.height},
                         {"spp", last.spp}, {"seconds", res.final_render.seconds},
                         {"estimated_relative_error", last.estimated_error},
                         {"stopped_by", res.final_render.stopped_by},
                         {"capped_paths", res.final_render.counters.capped_paths},
                         {"A_render", final_stats.a}};
    j["scene"] = {{"boundary", to_string(o.render.interface.mode)}, {"ior", o.render.interface.ior},
                  {"specular", o.render.interface.specular}, {"g", o.render.g},
                  {"light_dir", {o.render.light_direction.x, o.render.light_direction.y, o.render.light_direction.z}},
                  {"light_irradiance", o.render.light_irradiance},
                  {"light_radius_degrees", o.render.light_radius_degrees},
                  {"environment", o.render.environment}, {"environment_scale", o.render.environment_scale},
                  {"background", o.render.background}, {"seed", o.render.settings.seed},
                  {"max_depth", o.render.settings.integrator.max_depth},
                  {"light_nee", o.render.settings.integrator.light_through_boundary},
                  {"camera_origin", {prep->camera.origin.x, prep->camera.origin.y, prep->camera.origin.z}},
                  {"camera_target", {prep->camera.target.x, prep->camera.target.y, prep->camera.target.z}},
                  {"fov_degrees_horizontal", prep->camera.fov_degrees}};
    j["seconds"] = {{"inputs", res.seconds_photo}, {"volume", res.seconds_volume}, {"fit", res.seconds_fit},
                    {"final_render", res.seconds_render}, {"write", res.seconds_write},
                    {"total", total.seconds()}};
    j["peak_memory_bytes"] = peak_rss_bytes();
    j["warnings"] = res.warnings;
    write_text(out("report.json"), j.dump(2) + "\n");
    res.written.push_back(out("report.json"));
    res.seconds_total = total.seconds();
    return res;
}

}  // namespace jade
