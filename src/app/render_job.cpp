#include "jade/app/render_job.h"

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
#include <memory>

namespace jade {

namespace {

// Beside `out`, with the extension replaced (render.exr -> render.png).
std::string sibling(const std::string& out, const std::string& suffix) {
    std::filesystem::path p(out);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

}  // namespace

RenderJobResult run_render_job(const RenderJob& job, Progress* progress,
                               const std::function<void(const PassRecord&)>& on_pass) {
    job.settings.validate();
    if (job.mesh.empty()) throw Error("--mesh is required (or a --job that names one)");
    if (job.out.empty()) throw Error("--out is required (or a --job that names it)");
    if (!(job.exposure >= 0.f) || !std::isfinite(job.exposure))
        throw Error("--exposure must be a finite number >= 0 (0: the volume's fitted one, or 1)");
    if (job.volume.empty() == !(job.sigma_s || job.sigma_a))
        throw Error("give either --volume or a homogeneous medium (--sigma-s/--sigma-a)");
    if (job.volume.empty() && (job.ks || job.contrast))
        throw Error("--ks and --contrast apply to a jaderender --volume, not to a homogeneous medium");
    // Every output's folder is checked before any work, so none is written
    // unless all can be.
    std::string png = job.png == "auto" ? sibling(job.out, ".png") : job.png;
    if (png == job.out) png.clear();  // --out x.png: the PNG is the output itself
    const std::string csv =
        job.convergence == "auto"
            ? sibling(job.out, ".convergence.csv")  // one per render: several can share a folder
            : job.convergence;
    for (const std::string& path : {job.out, png, csv})
        if (!path.empty()) require_output_folder(path);
    RenderJobResult result;
    result.exposure = job.exposure > 0.f ? job.exposure : 1.f;
    const Stopwatch load_clock;
    const std::unique_ptr<PreparedScene> prep = prepare_scene(job);
    result.warnings = prep->warnings;
    const Cube& cube = prep->cube;

    // Medium.
    std::unique_ptr<Medium> medium;
    MaterialVolume volume;  // held here: the medium references its levels
    if (!job.volume.empty()) {
        if (is_material_vdb(job.volume)) {
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
            result.medium_description = text;
            if (job.exposure == 0.f && volume.exposure > 0.0) result.exposure = float(volume.exposure);
            medium = std::make_unique<MaterialVolumeMedium>(volume, cube);
        } else {
            if (job.ks) fail_file(job.volume, "--ks applies to jaderender volumes only");
            if (job.contrast) fail_file(job.volume, "--contrast applies to jaderender volumes only");
            CoefficientGrids grids = read_medium_vdb(job.volume, job.density);
            const auto& s = grids.placement.size;
            result.medium_description = "grids " + std::to_string(s[0]) + "x" + std::to_string(s[1]) +
                                        "x" + std::to_string(s[2]) + " from " + job.volume;
            medium = std::make_unique<FloatGridMedium>(std::move(grids));
        }
    } else {
        const Spectrum ss = job.sigma_s.value_or(Spectrum(0.f));
        const Spectrum sa = job.sigma_a.value_or(Spectrum(0.f));
        medium = std::make_unique<HomogeneousMedium>(ss, sa);
        char text[200];
        std::snprintf(text, sizeof text, "homogeneous, sigma_s (%g, %g, %g), sigma_a (%g, %g, %g)",
                      ss.x, ss.y, ss.z, sa.x, sa.y, sa.z);
        result.medium_description = text;
    }
    result.medium_bytes = medium->memory_bytes();
    prep->scene.medium = medium.get();
    const PinholeCamera camera(prep->camera);

    std::optional<ImageF32> reference;
    RenderSettings settings = job.settings;
    settings.backdrop = prep->backdrop;
    if (!job.reference.empty()) {
        reference = read_image_f32(job.reference);
        if (reference->width != job.width || reference->height != job.height)
            fail_file(job.reference, "is " + std::to_string(reference->width) + "x" +
                                         std::to_string(reference->height) + ", the render " +
                                         std::to_string(job.width) + "x" + std::to_string(job.height));
        settings.reference = &*reference;
    }
    result.load_seconds = load_clock.seconds();

    result.render = render(prep->scene, camera, settings, progress, on_pass);
    if (progress) progress->finish();

    write_film(result.render.film, job.out, png, job.transparent, result.exposure);
    result.written.push_back(job.out);
    if (!png.empty()) result.written.push_back(png);
    if (!csv.empty()) {
        write_convergence_csv(csv, result.render.passes);
        result.written.push_back(csv);
    }
    return result;
}

}  // namespace jade
