#include "jade/app/bench.h"

#include "jade/io/atomic_file.h"
#include "jade/core/error.h"
#include "jade/core/parse.h"
#include "jade/volume/material_volume.h"
#include "jade/render/media/grid.h"
#include "jade/render/media/homogeneous.h"
#include "jade/geometry/mesh_io.h"
#include "jade/geometry/mesh_accel.h"
#include "jade/render/renderer.h"
#include "jade/volume/photo.h"
#include "jade/volume/structure_estimate.h"
#include "jade/core/random.h"
#include "jade/core/timing.h"
#include "jade/app/job.h"
#include "jade/app/render_job.h"
#include "jade/io/vdb_io.h"

#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

namespace jade {

namespace {

// 512x512 stone: grey body with 10% rose veins, so joint matching has two
// colour families to keep apart.
Photo builtin_photo() {
    Photo p;
    p.path = "(built-in synthetic stone)";
    p.width = p.height = 512;
    SplitMix64 rng(2016);
    for (int i = 0; i < 512 * 512; ++i) {
        const int d = int(rng.below(31)) - 15;
        p.levels.push_back(rng.uniform() < 0.1
                               ? Rgb8{std::uint8_t(200 + d / 2), std::uint8_t(90 + d), std::uint8_t(100 + d)}
                               : Rgb8{std::uint8_t(150 + d), std::uint8_t(150 + d), std::uint8_t(145 + d)});
        p.foreground.push_back(1);
    }
    return p;
}

double best_of(int repeats, const std::function<void()>& stage) {
    double best = 1e300;
    for (int i = 0; i < std::max(1, repeats); ++i) {
        Stopwatch sw;
        stage();
        best = std::min(best, sw.seconds());
    }
    return best;
}

}  // namespace

int run_volume_benchmark(const VolumeBenchOptions& o) {
    const Photo photo = o.photo.empty() ? builtin_photo() : load_photo(o.photo);
    NoiseParams noise;
    noise.resolution = o.resolution;
    noise.validate();
    const double voxels = double(o.resolution) * o.resolution * o.resolution;

    std::printf("volume benchmark: %d^3 voxels, photo %s, %d threads, best of %d\n", o.resolution,
                photo.path.c_str(), tbb::info::default_concurrency(), o.repeats);
    std::printf("%-28s %10s %14s %12s\n", "stage", "seconds", "Mvoxels/s", "peak RSS");

    // The structure estimate (--structure photo, the default) before the
    // noise it chooses; the rows below build the paper's fBm.
    StructureEstimate estimate;
    const double te = best_of(o.repeats, [&] { estimate = estimate_structure(photo, noise); });
    std::printf("%-28s %10.3f %14s %12s   (%d candidate structures)\n", "structure estimate", te, "-",
                format_megabytes(double(peak_rss_bytes())).c_str(), estimate.evaluations);

    MaterialVolume vol;
    for (MatchMode mode : {MatchMode::PerChannel, MatchMode::Joint}) {
        const double t = best_of(o.repeats, [&] {
            vol = MaterialVolume{};  // measure one volume's memory, not two
            vol = build_material_volume(photo, noise, mode, OpticalParams{});
        });
        std::printf("%-28s %10.3f %14.1f %12s\n",
                    (std::string("noise + matching (") + to_string(mode) + ")").c_str(), t,
                    voxels / t / 1e6, format_megabytes(double(peak_rss_bytes())).c_str());
    }

    // The photo swept in depth (--structure exemplar), joint matching: no
    // noise to evaluate, the resampling and a copy per slice. Built into a
    // volume of its own, so that the file rows below write the fBm's.
    {
        NoiseParams swept = noise;
        swept.exemplar = true;
        MaterialVolume sv;
        const double t = best_of(o.repeats, [&] {
            sv = MaterialVolume{};
            sv = build_material_volume(photo, swept, MatchMode::Joint, OpticalParams{});
        });
        std::printf("%-28s %10.3f %14.1f %12s\n", "swept photo + matching", t, voxels / t / 1e6,
                    format_megabytes(double(peak_rss_bytes())).c_str());
    }

    const std::string dir = o.scratch_dir.empty() ? std::filesystem::temp_directory_path().string()
                                                  : o.scratch_dir;
    const std::string path = (std::filesystem::path(dir) / "jaderender-bench.vdb").string();
    const double tw = best_of(o.repeats, [&] { write_material_vdb(path, vol); });
    const double size = double(file_size(path));
    std::printf("%-28s %10.3f %14.1f %12s   (file %s)\n", "vdb write", tw, voxels / tw / 1e6,
                format_megabytes(double(peak_rss_bytes())).c_str(), format_megabytes(size).c_str());
    MaterialVolume back;
    const double tr = best_of(o.repeats, [&] { back = read_material_vdb(path); });
    std::printf("%-28s %10.3f %14.1f %12s\n", "vdb read", tr, voxels / tr / 1e6,
                format_megabytes(double(peak_rss_bytes())).c_str());
    std::filesystem::remove(path);
    std::printf("round trip exact: %s\n", back.levels == vol.levels ? "yes" : "NO");
    return back.levels == vol.levels ? 0 : 1;
}

int run_render_benchmark(const RenderBenchOptions& o) {
    if (!(o.target_error > 0.0)) throw Error("--target-error must be positive");
    const Photo photo = o.photo.empty() ? builtin_photo() : load_photo(o.photo);
    const TriangleMesh mesh = o.mesh.empty() ? icosphere(5, 1.f) : load_mesh(o.mesh);
    NoiseParams noise;
    noise.resolution = o.resolution;
    noise.validate();
    const Stopwatch build_clock;
    const MaterialVolume volume = build_material_volume(photo, noise, MatchMode::Joint, OpticalParams{});
    const double build_s = build_clock.seconds();

    const MeshAccel accel(mesh);
    const MaterialVolumeMedium medium(volume, bounding_cube(mesh));
    // The scene `jaderender render` sets up by default.
    const RenderJob defaults;
    Scene scene;
    scene.boundary = &accel;
    scene.medium = &medium;
    scene.interface = defaults.interface;
    scene.light = DirectionalLight(defaults.light_direction, defaults.light_irradiance,
                                   defaults.light_radius_degrees);
    Spectrum env;
    parse_vec3(defaults.environment, env);
    scene.environment = Environment(env);
    scene.fit_ray_epsilon();
    const PinholeCamera camera(frame_mesh(mesh.bounds(), o.width, o.height));

    RenderSettings settings;
    settings.spp = 1 << 20;
    settings.time_limit = o.max_seconds;
    settings.target_error = o.target_error;
    std::printf("render benchmark: volume %d^3 from %s (built in %.2f s), mesh %s (%zu triangles), "
                "%dx%d, %d threads; until estimated relative error %.3g or %.0f s\n",
                o.resolution, photo.path.c_str(), build_s, mesh.path.c_str(), mesh.triangles.size(),
                o.width, o.height, tbb::info::default_concurrency(), o.target_error, o.max_seconds);
    std::printf("%6s %8s %10s %12s\n", "pass", "spp", "seconds", "est. error");
    const RenderResult r = render(scene, camera, settings, nullptr, [](const PassRecord& p) {
        std::printf("%6d %8d %10.2f %12.4f\n", p.pass, p.spp, p.seconds, p.estimated_error);
        std::fflush(stdout);
    });
    const PassRecord& last = r.passes.back();
    const double samples = double(o.width) * o.height * last.mean_spp;
    const PathCounters& c = r.counters;
    const double collisions = double(c.real_collisions + c.null_collisions);
    std::printf("reached %.4f after %.2f s (%s; stopped by %s)\n", last.estimated_error, r.seconds,
                format_spp(last).c_str(), r.stopped_by.c_str());
    std::printf("samples/s %.3g, path vertices/s %.3g, vertices per path %.1f\n", samples / r.seconds,
                double(c.vertices()) / r.seconds, double(c.vertices()) / double(c.paths));
    std::printf("collisions: %.3g real, %.3g null (%.1f%% null); capped paths %llu\n",
                double(c.real_collisions), double(c.null_collisions),
                collisions > 0 ? 100.0 * double(c.null_collisions) / collisions : 0.0,
                (unsigned long long)c.capped_paths);
    std::printf("memory: medium %s, film %s, peak RSS %s\n",
                format_megabytes(double(medium.memory_bytes())).c_str(),
                format_megabytes(double(Film::memory_bytes(o.width, o.height))).c_str(),
                format_megabytes(double(peak_rss_bytes())).c_str());
    return 0;
}

int run_convergence_benchmark(const ConvergenceBenchOptions& o) {
    if (o.job.empty()) throw Error("bench convergence: --job is required");
    if (o.batches < 2 || (o.batches & (o.batches - 1)) != 0)
        throw Error("bench convergence: --batches must be a power of 2, at least 2");
    const RenderJob job = load_job(o.job);
    std::printf("convergence benchmark: %s, %dx%d, %d batches of %d spp, %d threads\n", o.job.c_str(), job.width,
                job.height, o.batches, o.batch_spp, tbb::info::default_concurrency());
    const RenderBatches b = render_job_batches(job, o.batches, o.batch_spp, [&](int j, double seconds) {
        std::printf("  batch %d: samples %d:%d in %.2f s\n", j, j * o.batch_spp, (j + 1) * o.batch_spp, seconds);
        std::fflush(stdout);
    });
    std::printf("medium: %s (loaded in %.2f s)\n", b.medium_description.c_str(), b.load_seconds);
    std::printf("%8s %10s %16s %16s\n", "spp", "seconds", "error (across)", "film's estimate");
    struct Row {
        int spp;
        double seconds, across, film;
    };
    std::vector<Row> rows;
    double total = 0.0;
    for (double t : b.seconds) total += t;
    for (int g = 1; g < o.batches; g *= 2) {
        std::vector<Film> groups;
        double film = 0.0;
        for (int a = 0; a < o.batches; a += g) {
            Film f = b.films[std::size_t(a)];
            for (int k = 1; k < g; ++k) f.merge(b.films[std::size_t(a + k)]);
            film += f.estimated_relative_error();
            groups.push_back(std::move(f));
        }
        const int n = o.batches / g;
        rows.push_back({g * o.batch_spp, total / n, Film::relative_error_across(groups), film / n});
    }
    Film whole = b.films[0];
    for (int k = 1; k < o.batches; ++k) whole.merge(b.films[std::size_t(k)]);
    rows.push_back({o.batches * o.batch_spp, total, rows[0].across / std::sqrt(double(o.batches)),
                    whole.estimated_relative_error()});
    for (const Row& r : rows) std::printf("%8d %10.2f %16.4f %16.4f\n", r.spp, r.seconds, r.across, r.film);
    const auto first = std::find_if(rows.begin(), rows.end(), [](const Row& r) { return r.spp >= 64; });
    const Row& last = rows.back();
    if (first != rows.end() && first->spp < last.spp) {
        // The batches cost alike, so seconds grow as the samples do and
        // one slope serves both.
        const double ls = std::log(double(last.spp) / first->spp);
        std::printf("log-log slope from %d to %d spp (%.3f s a sample per pixel): across %.3f, the film's "
                    "estimate %.3f (1/sqrt: -0.5)\n",
                    first->spp, last.spp, total / last.spp, std::log(last.across / first->across) / ls,
                    std::log(last.film / first->film) / ls);
    }
    return 0;
}

namespace {
struct FurnaceCase {
    double mean = 0, standard_error = 0, seconds = 0, setup_seconds = 0, table_mb = 0;
    int spp = 0;
    std::uint64_t capped = 0, walks = 0;
};

// One furnace render of the stiff benchmark (mean over all pixels, whose
// truth is 1; the standard error from the pixels' spread).
FurnaceCase furnace_case(const MeshAccel& accel, float sigma_t, bool walks, const StiffBenchOptions& o) {
    const HomogeneousMedium medium(Spectrum(sigma_t), Spectrum(0.f));
    Scene scene;
    scene.boundary = &accel;
    scene.medium = &medium;
    scene.interface.mode = BoundaryMode::Fresnel;
    scene.environment = Environment(Spectrum(1.f));
    scene.fit_ray_epsilon();
    CameraParams cp;
    cp.width = cp.height = o.width;
    const PinholeCamera camera(cp);
    RenderSettings settings;
    settings.spp = o.spp;
    settings.time_limit = o.seconds;
    settings.integrator.sphere_walks = walks;
    FurnaceCase out;
    const RenderResult r = render(scene, camera, settings);
    out.table_mb = double(r.sphere_exit_bytes) / 1e6;
    out.setup_seconds = r.setup_seconds;
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int y = 0; y < o.width; ++y)
        for (int x = 0; x < o.width; ++x) {
            if (r.film.samples(x, y) == 0) continue;
            const double v = average(r.film.mean(x, y));
            sum += v;
            sum2 += v * v;
            ++n;
        }
    out.mean = n ? sum / n : 0.0;
    out.standard_error = n > 1 ? std::sqrt(std::max(0.0, sum2 / n - out.mean * out.mean) / (n - 1)) : 0.0;
    out.seconds = r.seconds;
    out.spp = r.passes.empty() ? 0 : r.passes.back().spp;
    out.capped = r.counters.capped_paths;
    out.walks = r.counters.sphere_walks;
    return out;
}
}  // namespace

int run_stiff_benchmark(const StiffBenchOptions& o) {
    if (o.width < 1 || o.spp < 1 || !(o.seconds > 0.0) || !(o.max_sigma_t >= 1.0))
        throw Error("bench stiff: --width, --spp, --seconds and --max-sigma-t must be positive");
    const TriangleMesh mesh = icosphere(5, 1.f);
    const MeshAccel accel(mesh);
    std::printf("stiff-media benchmark: white furnace (albedo 1, unit sphere, fresnel boundary, unit sky; "
                "truth 1), %dx%d, up to %d spp or %.0f s a case, %d threads\n",
                o.width, o.width, o.spp, o.seconds, tbb::info::default_concurrency());
    std::printf("%9s %6s %9s %9s %6s %9s %10s %8s %9s %10s %10s\n", "sigma_t", "walks", "furnace", "std.err",
                "spp", "seconds", "us/sample", "setup s", "tables MB", "walks/path", "capped");
    for (double sigma_t = 1.0; sigma_t <= o.max_sigma_t * 1.0001; sigma_t *= 10.0)
        for (bool walks : {true, false}) {
            const FurnaceCase c = furnace_case(accel, float(sigma_t), walks, o);
            const double samples = double(o.width) * o.width * std::max(1, c.spp);
            std::printf("%9.0e %6s %9.4f %9.4f %6d %9.2f %10.1f %8.2f %9.1f %10.1f %10llu\n", sigma_t,
                        walks ? "on" : "off", c.mean, c.standard_error, c.spp, c.seconds,
                        1e6 * c.seconds / samples, c.setup_seconds, c.table_mb, double(c.walks) / samples,
                        (unsigned long long)c.capped);
            std::fflush(stdout);
        }
    return 0;
}

}  // namespace jade
