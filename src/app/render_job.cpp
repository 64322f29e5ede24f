#include "jade/app/render_job.h"

#include "jade/app/report.h"
#include "jade/io/atomic_file.h"
#include "jade/core/error.h"
#include "jade/io/image_io.h"
#include "jade/io/vdb_io.h"
#include "jade/render/media/grid.h"
#include "jade/render/media/homogeneous.h"
#include "jade/core/progress.h"
#include "jade/core/timing.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>

namespace jade {

namespace {

namespace fs = std::filesystem;

// The convergence picture beside its CSV (x.convergence.csv ->
// x.convergence.png); none when that name is the CSV itself or another of
// the render's outputs.
std::string convergence_plot_path(const std::string& csv, const std::string& out, const std::string& png) {
    if (csv.empty()) return "";
    const std::string plot = fs::path(csv).replace_extension(".png").string();
    return plot == csv || plot == out || plot == png ? "" : plot;
}

// The job's medium, and what it references, owned in one place.
struct LoadedMedium {
    MaterialVolume volume;  // a jaderender volume's levels, which the medium reads
    std::unique_ptr<Medium> medium;
    std::string description;
    float fitted_exposure = 0.f;  // a jaderender volume's, 0 otherwise
};

std::unique_ptr<LoadedMedium> load_medium(const RenderJob& job, const Cube& cube) {
    auto m = std::make_unique<LoadedMedium>();
    if (job.volume.empty()) {
        const Spectrum ss = job.sigma_s.value_or(Spectrum(0.f));
        const Spectrum sa = job.sigma_a.value_or(Spectrum(0.f));
        m->medium = std::make_unique<HomogeneousMedium>(ss, sa);
        char text[200];
        std::snprintf(text, sizeof text, "homogeneous, sigma_s (%g, %g, %g), sigma_a (%g, %g, %g)",
                      ss.x, ss.y, ss.z, sa.x, sa.y, sa.z);
        m->description = text;
    } else if (is_material_vdb(job.volume)) {
        MaterialVolume& volume = m->volume;
        volume = read_material_vdb(job.volume);
        if (job.ks) volume.optics.ks = {(*job.ks)[0], (*job.ks)[1], (*job.ks)[2]};
        if (job.contrast) volume.optics.contrast = {(*job.contrast)[0], (*job.contrast)[1], (*job.contrast)[2]};
        volume.optics.validate();
        char text[256];
        std::snprintf(text, sizeof text,
                      "jaderender volume %d^3 on the mesh's cube (side %.4g), k_s (%.3f, %.3f, %.3f), "
                      "contrast (%.3f, %.3f, %.3f)",
                      volume.resolution, cube.side, volume.optics.ks[0], volume.optics.ks[1],
                      volume.optics.ks[2], volume.optics.contrast[0], volume.optics.contrast[1],
                      volume.optics.contrast[2]);
        m->description = text;
        if (volume.exposure > 0.0) m->fitted_exposure = float(volume.exposure);
        m->medium = std::make_unique<MaterialVolumeMedium>(volume, cube);
    } else {
        if (job.ks) fail_file(job.volume, "--ks applies to jaderender volumes only");
        if (job.contrast) fail_file(job.volume, "--contrast applies to jaderender volumes only");
        CoefficientGrids grids = read_medium_vdb(job.volume, job.density);
        const auto& s = grids.placement.size;
        m->description = "grids " + std::to_string(s[0]) + "x" + std::to_string(s[1]) + "x" +
                         std::to_string(s[2]) + " from " + job.volume;
        m->medium = std::make_unique<FloatGridMedium>(std::move(grids));
    }
    return m;
}

// What any render of the job needs, its outputs aside.
void validate_scene_of(const RenderJob& job) {
    job.settings.validate();
    if (job.mesh.empty() == !job.sphere)
        throw Error("give either --mesh or --sphere (or a --job that names one)");
    if (!(job.exposure >= 0.f) || !std::isfinite(job.exposure))
        throw Error("--exposure must be a finite number >= 0 (0: the volume's fitted one, or 1)");
    if (job.volume.empty() == !(job.sigma_s || job.sigma_a))
        throw Error("give either --volume or a homogeneous medium (--sigma-s/--sigma-a)");
    if (job.volume.empty() && (job.ks || job.contrast))
        throw Error("--ks and --contrast apply to a jaderender --volume, not to a homogeneous medium");
}

void validate_job(const RenderJob& job) {
    validate_scene_of(job);
    if (job.out.empty()) throw Error("--out is required (or a --job that names it)");
}

// The job's scene with its medium in it, ready to render.
struct LoadedScene {
    std::unique_ptr<PreparedScene> prep;
    std::unique_ptr<LoadedMedium> medium;
};

LoadedScene load_scene(const RenderJob& job) {
    LoadedScene s{prepare_scene(job), nullptr};
    s.medium = load_medium(job, s.prep->cube);
    s.prep->scene.medium = s.medium->medium.get();
    return s;
}

// A piece of the render: its range only, written as a piece file.
void render_piece(const RenderJob& job, const PieceRange& piece, const Scene& scene, const PinholeCamera& camera,
                  const RenderSettings& settings, const std::string& path, Progress* progress,
                  RenderJobResult& result) {
    const Stopwatch clock;
    RenderResult& r = result.render;
    r.film = render_pass(scene, camera, settings, piece.samples, piece.pixels, &r.counters, progress);
    r.seconds = clock.seconds();
    r.stopped_by = "range";
    PassRecord rec;
    rec.spp = piece.samples.last - piece.samples.first;
    rec.mean_spp = double(rec.spp);
    rec.seconds = r.seconds;
    rec.estimated_error = r.film.estimated_relative_error();
    r.passes.push_back(rec);
    if (progress) progress->finish();
    write_render_piece(path, job, piece, r.film, result.exposure, r.seconds);
    result.written.push_back(path);
}

}  // namespace

RenderBatches render_job_batches(const RenderJob& job, int batches, int batch_spp,
                                 const std::function<void(int, double)>& on_batch) {
    validate_scene_of(job);
    if (batches < 2 || batch_spp < 2) throw Error("--batches and --batch-spp must be at least 2");
    if (double(batches) * batch_spp > double(std::numeric_limits<int>::max()))
        throw Error("--batches times --batch-spp is too many samples per pixel");
    RenderBatches out;
    const Stopwatch load_clock;
    const LoadedScene loaded = load_scene(job);
    const PreparedScene* prep = loaded.prep.get();
    out.medium_description = loaded.medium->description;
    const PinholeCamera camera(prep->camera);
    RenderSettings settings = job.settings;
    settings.backdrop = prep->backdrop;
    settings.spp = batches * batch_spp;
    out.load_seconds = load_clock.seconds();
    const PixelBounds all{0, 0, job.width, job.height};
    for (int j = 0; j < batches; ++j) {
        const Stopwatch clock;
        out.films.push_back(
            render_pass(prep->scene, camera, settings, SampleRange{j * batch_spp, (j + 1) * batch_spp}, all));
        out.seconds.push_back(clock.seconds());
        if (on_batch) on_batch(j, out.seconds.back());
    }
    return out;
}

RenderJobResult run_render_job(const RenderJob& job, Progress* progress,
                               const std::function<void(const PassRecord&)>& on_pass, const PieceRange* piece) {
    validate_job(job);
    if (piece) validate_piece(job, *piece);
    // Every output's folder is checked before any work, so none is written
    // unless all can be. A piece writes only its own file.
    std::string png = job.png == "auto" ? sibling_path(job.out, ".png") : job.png;
    if (png == job.out) png.clear();  // --out x.png: the PNG is the output itself
    std::string csv = job.convergence == "auto"
                          ? sibling_path(job.out, ".convergence.csv")  // one per render: several can share a folder
                          : job.convergence;
    const std::string out = piece ? piece_path(job.out, *piece, job.width, job.height) : job.out;
    if (piece) {
        png.clear();
        csv.clear();
    }
    const std::string plot = convergence_plot_path(csv, job.out, png);
    for (const std::string& path : {out, png, csv, plot})
        if (!path.empty()) require_output_folder(path);
    RenderJobResult result;
    const Stopwatch load_clock;
    const LoadedScene loaded = load_scene(job);
    const PreparedScene* prep = loaded.prep.get();
    const LoadedMedium* medium = loaded.medium.get();
    result.warnings = prep->warnings;
    result.medium_description = medium->description;
    result.medium_bytes = medium->medium->memory_bytes();
    result.exposure = job.exposure > 0.f ? job.exposure : medium->fitted_exposure > 0.f ? medium->fitted_exposure : 1.f;
    const PinholeCamera camera(prep->camera);

    std::optional<ImageF32> reference;
    RenderSettings settings = job.settings;
    settings.backdrop = prep->backdrop;
    if (!job.reference.empty() && !piece) {
        reference = read_image_f32(job.reference);
        if (reference->width != job.width || reference->height != job.height)
            fail_file(job.reference, "is " + std::to_string(reference->width) + "x" +
                                         std::to_string(reference->height) + ", the render " +
                                         std::to_string(job.width) + "x" + std::to_string(job.height));
        settings.reference = &*reference;
    }
    result.load_seconds = load_clock.seconds();

    if (piece) {
        render_piece(job, *piece, prep->scene, camera, settings, out, progress, result);
        return result;
    }
    result.render = render(prep->scene, camera, settings, progress, on_pass);
    if (progress) progress->finish();
    if (const std::size_t n = result.render.unsampled_pixels; n > 0)
        result.warnings.push_back("--time " + std::to_string(job.settings.time_limit) + " s ran out before every pixel "
                                  "had a sample: " + std::to_string(n) + " of " +
                                  std::to_string(std::size_t(job.width) * job.height) +
                                  " pixels are black (no sample); give more time");

    write_film(result.render.film, job.out, png, job.transparent, result.exposure);
    result.written.push_back(job.out);
    if (!png.empty()) result.written.push_back(png);
    if (!csv.empty()) {
        write_convergence_csv(csv, result.render.passes);
        result.written.push_back(csv);
    }
    if (!plot.empty()) {
        const RgbImage8 picture =
            convergence_plot(result.render.passes, fs::path(job.out).filename().string());
        write_image_u8(plot, picture.width, picture.height, 3, picture.pixels);
        result.written.push_back(plot);
    }
    return result;
}

}  // namespace jade
