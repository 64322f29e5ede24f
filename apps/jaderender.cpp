// jaderender: the command-line front end. It parses flags and calls the
// library; all the work lives in libjade.

#include "jade/atomic_file.h"
#include "jade/bench.h"
#include "jade/error.h"
#include "jade/image_io.h"
#include "jade/material_volume.h"
#include "jade/photo.h"
#include "jade/progress.h"
#include "jade/report.h"
#include "jade/vdb_io.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

namespace {

struct VolumeOptions {
    std::string photo, mask, out, preview;
    jade::NoiseParams noise;
    std::string match = "joint";
    jade::OpticalParams optics;
};

void add_volume_flags(CLI::App& cmd, VolumeOptions& o) {
    cmd.add_option("--photo", o.photo, "Photograph of the material (PNG, JPEG, TIFF, EXR; "
                                       "alpha >= 0.5 marks the object)")
        ->required();
    cmd.add_option("--mask", o.mask, "Mask image, same size as the photo; white (>= 0.5) = "
                                     "object. Replaces the photo's alpha");
    cmd.add_option("--resolution", o.noise.resolution, "Voxels along each side of the cube (s)")
        ->capture_default_str();
    cmd.add_option("--octaves", o.noise.octaves, "fBm octaves n (0 = floor(log2(s)), the paper's)")
        ->capture_default_str();
    cmd.add_option("--k", o.noise.k, "fBm amplitude ratio k, 0 < k < 1")->capture_default_str();
    cmd.add_option("--seed", o.noise.seed, "Noise seed")->capture_default_str();
    cmd.add_option("--match", o.match, "Colour matching: 'joint' (real photo colours) or "
                                       "'per-channel' (the paper's)")
        ->capture_default_str();
    cmd.add_option("--ds", o.optics.ds, "Scattering scale d_s")->capture_default_str();
    cmd.add_option("--da", o.optics.da, "Absorption scale d_a")->capture_default_str();
    cmd.add_option("--density-scale", o.optics.density_scale,
                   "Optical thickness across the object for a coefficient of 1")
        ->capture_default_str();
}

int run_volume(const VolumeOptions& o) {
    const jade::Stopwatch total;
    const jade::MatchMode match = jade::parse_match_mode(o.match);
    o.noise.validate();
    o.optics.validate();

    const jade::Stopwatch t_photo;
    const jade::Photo photo = jade::load_photo(o.photo, o.mask);
    const double photo_s = t_photo.seconds();

    const jade::Stopwatch t_volume;
    jade::MaterialVolume volume;
    {
        jade::Progress progress("noise + colour matching", std::size_t(o.noise.resolution));
        volume = jade::build_material_volume(photo, o.noise, match, o.optics, &progress);
    }
    const double volume_s = t_volume.seconds();

    const jade::Stopwatch t_write;
    jade::write_material_vdb(o.out, volume);
    const double write_s = t_write.seconds();

    if (!o.preview.empty())
        jade::write_image_u8(o.preview, volume.resolution, volume.resolution, 3,
                             jade::slice_image(volume, volume.resolution / 2));

    std::printf("volume: %d^3 = %.1f M voxels (%s match, %zu foreground pixels); photo %.2f s, "
                "noise+matching %.2f s, vdb write %.2f s; %s %s; total %.2f s, peak memory %s\n",
                volume.resolution, double(volume.levels.size()) / 1e6, jade::to_string(match),
                photo.foreground_count(), photo_s, volume_s, write_s, o.out.c_str(),
                jade::format_megabytes(double(jade::file_size(o.out))).c_str(), total.seconds(),
                jade::format_megabytes(double(jade::peak_rss_bytes())).c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jaderender: Monte Carlo rendering and fitting of heterogeneous translucent "
                 "materials (jade, marble) from one photograph"};
    app.set_version_flag("--version", std::string(JADE_VERSION));
    app.require_subcommand(1);

    VolumeOptions vol;
    auto* volume_cmd = app.add_subcommand(
        "volume", "Build the material volume from a photo (noise -> colour matching -> "
                  "coefficients) and write it as .vdb");
    add_volume_flags(*volume_cmd, vol);
    volume_cmd->add_option("--out", vol.out, "Output .vdb file")->required();
    volume_cmd->add_option("--preview", vol.preview,
                           "Also write the middle slice of the matched noise as an image");

    jade::VolumeBenchOptions bench;
    auto* bench_cmd = app.add_subcommand(
        "bench", "Benchmark the pipeline's stages (time, throughput, peak memory)");
    bench_cmd->add_option("--resolution", bench.resolution, "Voxels along each side")
        ->capture_default_str();
    bench_cmd->add_option("--photo", bench.photo,
                          "Photo to match (default: a built-in synthetic stone)");
    bench_cmd->add_option("--repeats", bench.repeats, "Runs per stage; the best is reported")
        ->capture_default_str();
    bench_cmd->add_option("--scratch", bench.scratch_dir,
                          "Folder for the temporary .vdb (default: the system's temp folder)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "jaderender: error: %s (see --help)\n",
                     jade::Error(e.what()).what());
        return 2;
    }

    try {
        if (*volume_cmd) return run_volume(vol);
        if (*bench_cmd) return jade::run_volume_benchmark(bench);
    } catch (const jade::Error& e) {
        std::fprintf(stderr, "jaderender: error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "jaderender: internal error: %s\n", jade::Error(e.what()).what());
        return 3;
    }
    return 0;
}
