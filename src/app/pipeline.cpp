#include "jade/app/pipeline.h"

#include "jade/app/blender_script.h"
#include "jade/app/report.h"
#include "jade/core/error.h"
#include "jade/core/progress.h"
#include "jade/core/timing.h"
#include "jade/fit/compare.h"
#include "jade/io/atomic_file.h"
#include "jade/io/gltf_preview.h"
#include "jade/io/image_io.h"
#include "jade/io/vdb_io.h"
#include "jade/render/media/grid.h"
#include "jade/volume/photo.h"
#include "jade/volume/sharpen.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

namespace jade {

namespace {

namespace fs = std::filesystem;

// The output folder, refused before any work when its parent does not exist.
std::string output_folder(const PipelineOptions& o) {
    const std::string dir = o.out_dir.empty() ? default_out_dir(o.photo) : o.out_dir;
    const fs::path parent = fs::path(dir).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec))
        fail_file(dir, "the folder '" + parent.string() + "' does not exist");
    return dir;
}

// The volume read from --volume, or built from the photo with the structure
// chosen (and, for an estimate, reported) first.
MaterialVolume make_volume(const PipelineOptions& o, const Photo& photo, const Cube& cube, PipelineResult& res) {
    if (!o.volume.empty()) {
        MaterialVolume volume = read_material_vdb(o.volume);
        volume.cube = cube;
        if (volume.photo_span != photo.span) {
            char text[200];
            std::snprintf(text, sizeof text,
                          "%s was matched to a photo spanning %g cube sides; the photo is measured at --photo-span %g",
                          o.volume.c_str(), volume.photo_span, photo.span);
            res.warnings.push_back(text);
        }
        return volume;
    }
    const Stopwatch clock;
    res.structure_estimated = o.structure == StructureMode::Photo;
    const NoiseParams noise = choose_noise(photo, o.noise, o.structure, &res.structure);
    res.seconds_structure = clock.seconds();
    std::unique_ptr<Progress> bar;
    if (o.progress) bar = std::make_unique<Progress>("noise + colour matching", std::size_t(noise.resolution));
    MaterialVolume volume = build_material_volume(photo, noise, o.match, o.optics, bar.get());
    const std::string clipped = sharpening_warning(noise.sharpen, volume.sharpen_clipped);
    if (!clipped.empty()) res.warnings.push_back("volume: " + clipped);
    volume.structure = o.structure;
    volume.cube = cube;
    return volume;
}

// A volume and its fit: the session refers to the volume, so both live here
// (not movable).
struct FittedVolume {
    FittedVolume(MaterialVolume v, const PreparedScene& prep, const Photo& photo, const RenderSettings& settings,
                 const FitOptions& fit)
        : volume(std::move(v)), session(volume, prep.scene, prep.camera, settings, photo, fit) {}
    FittedVolume(const FittedVolume&) = delete;
    MaterialVolume volume;
    FitSession session;
    FitOutcome outcome;

    // Fits the volume, counting progress against `max_renders`, the fit's budget.
    void fit(const PipelineOptions& o, const char* label, int max_renders) {
        std::unique_ptr<Progress> bar;
        if (o.progress && o.fit.method != FitMethod::None)
            bar = std::make_unique<Progress>(label, std::size_t(max_renders));
        outcome = session.run(bar.get());
        volume.optics.ks = outcome.ks;
        volume.optics.contrast = outcome.contrast;
        volume.optics.density_scale = outcome.density_scale;
        volume.exposure = outcome.exposure;
    }
};

// Whether a sharper stone may follow the first fit
// (PipelineOptions::sharpen_from_fit): a volume built here, fitted by
// --fit contrast.
bool sharpens_after(const PipelineOptions& o) {
    return o.sharpen_from_fit && o.volume.empty() && o.fit.method == FitMethod::Contrast;
}

// The first fit's options: where a sharper stone may follow and the stone
// is sharpened less than kDefaultSharpen, the fit stops where the density
// scale reaches its ceiling, where sharpening_for would choose that stone
// anyway: its fit takes the search on from there, and the steps the first
// stone would have spent converging at the ceiling are not made (the demo:
// 6 renders fewer). Where it is sharpened less than kSharperStone, the fit
// stops also where the density scale's first rise meets the stone's need
// short of the ceiling, for that stone likewise (Onyx010 on the cow: 10
// renders fewer; docs/design.md, "Sharpening").
FitOptions first_fit_options(const PipelineOptions& o, const MaterialVolume& volume) {
    FitOptions fit = o.fit;
    fit.stop_at_density_ceiling = sharpens_after(o) && volume.noise.sharpen < kDefaultSharpen;
    fit.stop_at_first_rise = sharpens_after(o) && volume.noise.sharpen < kSharperStone;
    return fit;
}

// A fit of `volume` from `from`'s outcome (FitStart) within `max_renders`
// (at least kMinContrastRenders): the sharper stone's, or the first stone's
// resumed where it stopped for the sharper one.
std::unique_ptr<FittedVolume> fit_from(const PipelineOptions& o, const Photo& photo, const PreparedScene& prep,
                                       MaterialVolume volume, const FitOutcome& from, int max_renders,
                                       const char* label) {
    volume.optics.density_scale = from.density_scale;
    FitOptions fit = o.fit;
    fit.start = start_from(from);
    fit.max_renders = std::max(kMinContrastRenders, max_renders);
    auto next = std::make_unique<FittedVolume>(std::move(volume), prep, photo, o.render.settings, fit);
    next->fit(o, label, fit.max_renders);
    return next;
}

// The sharper stone (PipelineOptions::sharpen_from_fit): the sharpening
// `first`'s fit asks for (sharpening_for), where it is more than its own,
// fitted from that fit's outcome with half its budget of renders, and kept
// where that fit converges. Where the first fit stopped for it (at the
// density scale's ceiling or first rise) and the sharper stone's does not
// converge from there, the first stone's fit goes on from its stop with
// what was left of its budget (as a first fit not asked to stop would
// have). Returns the volume and fit kept.
std::unique_ptr<FittedVolume> fit_sharper_stone(const PipelineOptions& o, const Photo& photo,
                                                const PreparedScene& prep, std::unique_ptr<FittedVolume> first,
                                                PipelineResult& res) {
    if (!sharpens_after(o)) return first;
    const SharpeningChoice choice = sharpening_for(first->outcome);
    SharperStone& sharper = res.sharper.emplace();
    sharper.first = first->volume.noise.sharpen;
    sharper.sharper = choice.amount;
    sharper.why = choice.why;
    sharper.tried = choice.amount > sharper.first;
    sharper.from_stop = stopped_for_sharper_stone(first->outcome);
    if (!sharper.tried) return first;
    const Stopwatch clock;
    NoiseParams noise = first->volume.noise;
    noise.sharpen = choice.amount;
    std::unique_ptr<Progress> bar;
    if (o.progress) bar = std::make_unique<Progress>("the sharper stone's levels", std::size_t(noise.resolution));
    MaterialVolume volume = build_material_volume(photo, noise, o.match, o.optics, bar.get());
    bar.reset();
    volume.structure = first->volume.structure;
    volume.cube = first->volume.cube;
    sharper.sharper_began = first->outcome.seconds + clock.seconds();
    auto next = fit_from(o, photo, prep, std::move(volume), first->outcome, o.fit.max_renders / 2,
                         "fitting the sharper stone");
    sharper.seconds = clock.seconds();
    sharper.kept = next->outcome.converged;
    if (!sharper.kept) {
        sharper.other = next->outcome;
        if (!sharper.from_stop) return first;
        sharper.stopped = first->outcome;
        sharper.resumed_began = first->outcome.seconds + clock.seconds();
        auto resumed = fit_from(o, photo, prep, first->volume, first->outcome,
                                o.fit.max_renders - first->outcome.renders, "fitting the first stone on");
        sharper.seconds = clock.seconds();
        return resumed;
    }
    sharper.other = first->outcome;
    res.structure.chosen.noise.sharpen = noise.sharpen;  // the noise the volume written was built with
    const std::string clipped = sharpening_warning(noise.sharpen, next->volume.sharpen_clipped);
    if (!clipped.empty()) res.warnings.push_back("volume: the sharper stone's " + clipped);
    return next;
}

// The final render's settings. With `spp` > 0 exactly that many samples
// per pixel, whatever stopped the final render: a render that must share
// its random numbers takes the same samples.
RenderSettings final_settings(const PipelineOptions& o, const PreparedScene& prep, int spp = 0) {
    RenderSettings settings = o.render.settings;
    settings.backdrop = prep.backdrop;
    if (spp > 0) {
        settings.spp = spp;
        settings.time_limit = 0.0;
        settings.target_error = 0.0;
    }
    return settings;
}

std::unique_ptr<Progress> render_bar(const PipelineOptions& o, const PreparedScene& prep,
                                     const RenderSettings& settings, const char* label) {
    if (!o.progress) return nullptr;
    return std::make_unique<Progress>(label, std::size_t(prep.camera.width) * prep.camera.height * settings.spp);
}

// `medium` at the final render's size, seed and `spp`, in halves and
// quarters (material_spread extrapolates from both).
SplitFilms final_quarters(const PipelineOptions& o, const PreparedScene& prep, const Medium& medium, int spp,
                          const char* label) {
    Scene scene = prep.scene;
    scene.medium = &medium;
    const RenderSettings settings = final_settings(o, prep, spp);
    const std::unique_ptr<Progress> bar = render_bar(o, prep, settings, label);
    return render_quarters(scene, PinholeCamera(prep.camera), settings, nullptr, bar.get());
}

// The goal's reach at other translucencies (PipelineOptions::reach_densities):
// the shading at each density scale, its majorant floor the fitted one's
// scaled with it, so that at the fitted density it is the measure's own
// shading render, tentative collisions and all.
std::vector<ShadingReach> reach_by_density(const PipelineOptions& o, const PreparedScene& prep,
                                           const MaterialVolume& volume, const OpticalParams& mean_medium,
                                           const Spectrum& fitted_majorant, const Photo& photo, float exposure,
                                           int spp) {
    std::vector<ShadingReach> out;
    for (double density : o.reach_densities) {
        const Stopwatch clock;
        OpticalParams optics = mean_medium;
        optics.density_scale = density;
        const float scale = float(density / mean_medium.density_scale);
        const MaterialVolumeMedium shading(volume, volume.cube, optics, fitted_majorant * scale);
        char label[64];
        std::snprintf(label, sizeof label, "shading render at density %g", density);
        const SplitFilms flat = final_quarters(o, prep, shading, spp, label);
        ShadingReach r = shading_reach(photo, flat.merged(), exposure, render_pixels_per_side(prep.camera, volume.cube));
        r.density_scale = density;
        r.seconds = clock.seconds();
        out.push_back(r);
    }
    return out;
}

// The material against the photo (fit/appearance.h, compare_material): the
// fitted volume and its shading render (the mean medium under the same
// majorant: the same tentative collisions), both at the final render's
// samples and seed in halves and quarters, so that the noise can be taken out.
MaterialAppearance measure_material(const PipelineOptions& o, const PreparedScene& prep,
                                    const MaterialVolume& volume, const Photo& photo, PipelineResult& res) {
    const Stopwatch clock;
    const int spp = std::max(4, res.final_render.passes.empty() ? 4 : res.final_render.passes.back().spp);
    const MaterialVolumeMedium fitted(volume, volume.cube);
    OpticalParams mean_medium = volume.optics;
    mean_medium.contrast = {0.0, 0.0, 0.0};
    const MaterialVolumeMedium shading(volume, volume.cube, mean_medium, fitted.majorant());
    const SplitFilms render = final_quarters(o, prep, fitted, spp, "material render");
    const SplitFilms flat = final_quarters(o, prep, shading, spp, "shading render");
    MaterialAppearance m =
        compare_material(photo, render, flat, float(res.fit.exposure), render_pixels_per_side(prep.camera, volume.cube));
    res.seconds_measure = clock.seconds();  // the comparison's fits too, not the renders alone
    // Each row holds its own seconds.
    res.reach = reach_by_density(o, prep, volume, mean_medium, fitted.majorant(), photo, float(res.fit.exposure), spp);
    return m;
}

// The final render of the fitted volume, able to pause (ProgressiveRender):
// the medium at the volume's optics as they are when it is made, the scene
// holding it, and its progress bar. Not movable: the scene points at the
// medium.
struct FinalRender {
    FinalRender(const PipelineOptions& o, const PreparedScene& prep, const MaterialVolume& volume)
        : medium(volume, volume.cube), scene(with_medium(prep.scene, medium)), settings(final_settings(o, prep)),
          bar(render_bar(o, prep, settings, "final render")), render(scene, PinholeCamera(prep.camera), settings) {}
    FinalRender(const FinalRender&) = delete;
    static Scene with_medium(Scene scene, const Medium& medium) {
        scene.medium = &medium;
        return scene;
    }
    MaterialVolumeMedium medium;
    Scene scene;
    RenderSettings settings;
    std::unique_ptr<Progress> bar;
    ProgressiveRender render;
};

// The samples per pixel the brightness check renders at full size with: a
// quarter of the final render's, at least 64.
int check_spp(const PipelineOptions& o) { return std::max(64, o.render.settings.spp / 4); }

// Whether the brightness check reads A at full size from the final render's
// first check_spp samples (made once, and carried on from where k_s stays:
// on Marble021 and the bunny a quarter of the final render, 25 s, no longer
// made twice) rather than from a render of its own: where it must render at
// full size at all (FitSession::brightness_from_fit), and the final render
// has more samples than that and no time budget or target error, which
// could stop it short of them.
bool check_reads_final_render(const PipelineOptions& o, const FitSession& session) {
    const RenderSettings& s = o.render.settings;
    return !session.brightness_from_fit() && s.spp > check_spp(o) && s.time_limit == 0.0 && s.target_error == 0.0;
}

// At the final render's size A differs from the fitting renders'
// (FitSession::final_brightness): taken from --fit contrast's renders at that
// size, or else measured at a quarter of the final render's samples (at
// least 64), from `final_render`'s first ones where given; where a channel
// is foreseen off by 0.4 of the tolerance or more, its k_s moves before the
// final render.
void check_final_brightness(const PipelineOptions& o, const FitSession& session, MaterialVolume& volume,
                            FinalRender* final_render, PipelineResult& res) {
    const Stopwatch clock;
    BrightnessCheck check;
    const int spp = check_spp(o);
    // The object alone, as the fit measured it (docs/design.md, "The
    // backdrop"): the final render's samples less the backdrop's share.
    std::optional<Film> object_alone;
    if (final_render) {
        const Film& film = final_render->render.result().film;
        object_alone.emplace(film.width(), film.height());
        final_render->render.run_to(spp, final_render->bar.get(), nullptr, &*object_alone);
    }
    const FitSession::FinalBrightness f = session.final_brightness(spp, object_alone ? &*object_alone : nullptr);
    check.seconds = clock.seconds();
    check.spp = f.spp;
    check.from_fit = f.from_fit;
    check.from_final_render = f.from_final_render;
    check.delta = f.delta;
    check.size_change = f.size_change;
    check.expected = f.expected;
    check.renders = f.renders;
    check.white_share = f.white_share;
    check.noise_clipped = f.noise_clipped;
    check.ks_before = volume.optics.ks;
    check.ks_after = f.ks;
    volume.optics.ks = f.ks;
    res.brightness_check = check;
}

// The brightness check, then the final render: carried on from the
// check's samples where it read them and kept k_s, else made whole.
void check_and_render(const PipelineOptions& o, const PreparedScene& prep, const FitSession& session,
                      MaterialVolume& volume, PipelineResult& res) {
    Stopwatch clock;
    std::unique_ptr<FinalRender> final_render;
    if (o.final_match && o.fit.method != FitMethod::None) {
        if (check_reads_final_render(o, session)) final_render = std::make_unique<FinalRender>(o, prep, volume);
        check_final_brightness(o, session, volume, final_render.get(), res);
        if (res.brightness_check->corrected()) final_render.reset();
    }
    res.seconds_check = clock.seconds();
    clock = Stopwatch();
    if (!final_render) final_render = std::make_unique<FinalRender>(o, prep, volume);
    final_render->render.run_to(final_render->settings.spp, final_render->bar.get());
    res.final_render = std::move(final_render->render).take();
    res.seconds_render = clock.seconds();
}

// The final render as a job that replays it from the written volume, with the
// camera it used and the fitted exposure.
RenderJob replay_job(const PipelineOptions& o, const PreparedScene& prep, const std::string& dir,
                     float exposure) {
    RenderJob job = o.render;
    job.volume = (fs::path(dir) / "volume.vdb").string();
    job.ks.reset();
    job.contrast.reset();
    job.sigma_s.reset();
    job.sigma_a.reset();
    job.camera_file.clear();
    job.camera_origin = prep.camera.origin;
    job.camera_target = prep.camera.target;
    job.camera_target_given = true;
    job.camera_up = prep.camera.up;
    job.fov_degrees = prep.camera.fov_degrees;
    job.out = (fs::path(dir) / "render.exr").string();
    job.png = "auto";
    job.convergence = "auto";
    job.exposure = exposure;
    if (!job.light_file.empty()) {  // the file's light, for readers that cannot load it (docs/blender.md)
        job.light_direction = prep.scene.light.direction();
        job.light_irradiance = prep.scene.light.irradiance();
        job.light_file_resolved = true;
    }
    return job;
}

// fit.csv's rows: those of each fit in the order they ran, their
// iterations and seconds running on.
std::vector<FitRecord> fit_rows(const PipelineResult& res) {
    std::vector<FitRecord> rows;
    for (const FitLeg& leg : fit_legs(res)) {
        const int before = int(rows.size());
        for (FitRecord r : leg.fit->records) {
            r.iteration += before;
            r.seconds += leg.began;
            rows.push_back(r);
        }
    }
    return rows;
}

void write_outputs(const PipelineOptions& o, PipelineResult& res, const MaterialVolume& volume,
                   const Photo& photo, const PreparedScene& prep) {
    const Stopwatch clock;
    std::error_code ec;
    fs::create_directories(res.out_dir, ec);
    if (ec) fail_file(res.out_dir, "cannot create the output folder: " + ec.message());
    auto out = [&](const char* name) { return (fs::path(res.out_dir) / name).string(); };
    // report.json is the set's manifest, written last: an earlier run's goes
    // first, so a run stopped half way leaves none, and no report.json
    // vouches for a mix of two runs' files.
    fs::remove(out("report.json"), ec);
    const float exposure = res.fit.exposure;
    // The coefficient grids only inside the mesh (other tools see the stone,
    // not a block of fog); the levels cover the cube for any other mesh.
    write_material_vdb(out("volume.vdb"), volume, VdbLayout{&prep.mesh, o.vdb_z_up, o.vdb_color_name});
    write_film(res.final_render.film, out("render.exr"), out("render.png"), prep.backdrop.transparent, exposure);
    const std::vector<FitRecord> rows = fit_rows(res);
    write_text_file(out("fit.csv"), fit_csv(rows));
    write_convergence_csv(out("convergence.csv"), res.final_render.passes);
    const RgbImage8 conv = convergence_plot(res.final_render.passes, "final render");
    write_image_u8(out("convergence.png"), conv.width, conv.height, 3, conv.pixels);
    const RgbImage8 fitp = fit_plot(rows, res.fit.limits.tolerance);
    write_image_u8(out("fit.png"), fitp.width, fitp.height, 3, fitp.pixels);
    const DisplayStatistics final_stats = display_statistics(res.final_render.film, exposure, LumaHalves::Measure);
    const RgbHistogram photo_histogram = RgbHistogram::of(photo.foreground_levels());
    res.final_look = compare_appearance(photo_histogram, photo_spectrum(photo), final_stats,
                                        render_pixels_per_side(prep.camera, volume.cube));
    const RgbImage8 slice = slice_image(volume, volume.resolution / 2);
    char render_caption[96] = "render";
    if (!res.final_render.passes.empty()) {
        const PassRecord& last = res.final_render.passes.back();
        std::snprintf(render_caption, sizeof render_caption, "render %d spp, error %.2f", last.spp,
                      last.estimated_error);
    }
    const RgbImage8 cmp = compare_image({photo, res.final_render.film, exposure, slice, photo_histogram,
                                         final_stats.histogram, res.final_look, render_caption,
                                         "slice z = " + std::to_string(volume.resolution / 2)});
    write_image_u8(out("compare.png"), cmp.width, cmp.height, 3, cmp.pixels);
    // The Blender import (docs/blender.md), run as it is: it reads the
    // report.json beside it.
    write_text_file(out("blender.py"), kBlenderScript);
    // The mesh with one homogeneous stand-in for the material, for web and
    // real-time viewers (docs/preview.md).
    const MeanCoefficients mean = mean_coefficients(volume);
    const BoundaryParams& boundary = o.render.interface;
    res.preview = gltf_preview_material(mean.sigma_s, mean.sigma_a, o.render.g,
                                        boundary.mode == BoundaryMode::None ? 1.0 : boundary.ior,
                                        mean_chord_length(prep.mesh));
    write_preview_glb(out("preview.glb"), prep.mesh, res.preview);
    for (const char* name : {"volume.vdb", "render.exr", "render.png", "fit.csv", "convergence.csv", "convergence.png",
                             "fit.png", "compare.png", "blender.py", "preview.glb"})
        res.written.push_back(out(name));
    const RenderJob replay = replay_job(o, prep, res.out_dir, exposure);
    res.seconds_write = clock.seconds();
    res.seconds_total += res.seconds_write;
    write_text_file(out("report.json"),
               pipeline_report({o, res, volume, photo, final_stats, replay, res.out_dir}));
    res.written.push_back(out("report.json"));
}

}  // namespace

std::string default_out_dir(const std::string& photo) {
    return fs::path(photo).stem().string() + "-jaderender";
}

std::vector<FitLeg> fit_legs(const PipelineResult& res) {
    if (!res.sharper || !res.sharper->tried) return {{&res.fit, 0.0}};
    const SharperStone& sh = *res.sharper;
    if (sh.kept) return {{&sh.other, 0.0}, {&res.fit, sh.sharper_began}};
    if (sh.stopped) return {{&*sh.stopped, 0.0}, {&sh.other, sh.sharper_began}, {&res.fit, sh.resumed_began}};
    return {{&res.fit, 0.0}, {&sh.other, sh.sharper_began}};
}

int fit_renders(const PipelineResult& res) {
    int renders = 0;
    for (const FitLeg& leg : fit_legs(res)) renders += leg.fit->renders;
    return renders;
}

void validate_reach_densities(const std::vector<double>& densities) {
    for (double density : densities)
        if (!(density > 0.0) || !std::isfinite(density))
            throw Error("--densities must be positive numbers, got " + std::to_string(density));
}

PipelineResult run_pipeline(const PipelineOptions& o) {
    const Stopwatch total;
    o.noise.validate();
    o.optics.validate();
    validate_reach_densities(o.reach_densities);
    o.render.settings.validate();
    o.fit.validate();
    PipelineResult res;
    res.out_dir = output_folder(o);
    if (o.volume.empty()) require_memory_for_volume(o.noise.resolution);

    Stopwatch clock;
    const Photo photo = load_photo(o.photo, o.mask, o.photo_span);
    const std::unique_ptr<PreparedScene> prep = prepare_scene(o.render);
    res.warnings = prep->warnings;
    res.seconds_photo = clock.seconds();

    clock = Stopwatch();
    MaterialVolume volume = make_volume(o, photo, prep->cube, res);
    res.seconds_volume = clock.seconds();

    const FitOptions first_fit = first_fit_options(o, volume);
    auto fitted = std::make_unique<FittedVolume>(std::move(volume), *prep, photo, o.render.settings, first_fit);
    fitted->fit(o, o.fit.method == FitMethod::Contrast ? "fitting k_s and contrast" : "fitting k_s",
                o.fit.max_renders);
    res.seconds_fit = fitted->outcome.seconds;
    fitted = fit_sharper_stone(o, photo, *prep, std::move(fitted), res);
    if (res.sharper) res.seconds_fit += res.sharper->seconds;
    res.slices = measure_slice_structure(fitted->volume.levels, fitted->volume.resolution, photo);
    res.slices_across = measure_slice_structure_across(fitted->volume.levels, fitted->volume.resolution, photo);
    res.fit = fitted->outcome;
    for (const std::string& w : res.fit.warnings) res.warnings.push_back("fit: " + w);
    check_and_render(o, *prep, fitted->session, fitted->volume, res);
    if (o.measure_material) res.material = measure_material(o, *prep, fitted->volume, photo, res);

    res.seconds_total = total.seconds();
    write_outputs(o, res, fitted->volume, photo, *prep);
    res.seconds_total = total.seconds();
    return res;
}

}  // namespace jade
