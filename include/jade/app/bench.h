#pragma once
// Benchmarks: speed and memory of the pipeline's stages on built-in inputs,
// printed as a table. Measured here, never by timed tests.

#include "jade/app/pipeline.h"

#include <cstdint>
#include <array>
#include <string>
#include <vector>

namespace jade {

struct VolumeBenchOptions {
    int resolution = 256;
    std::string photo;       // empty: a built-in synthetic two-colour stone photo
    std::string scratch_dir; // where the .vdb is written and read back (removed after)
    int repeats = 3;         // each timed stage runs this often; the best time is reported
};

// Noise + matching, the .vdb write and read: wall time per stage (best of
// `repeats`), voxels per second, file size and the process's peak memory
// after the in-memory stages and after the file stages. Returns 0.
int run_volume_benchmark(const VolumeBenchOptions& options);

// Rendering: the material volume (from `photo`, or the built-in stone) in a
// mesh (`mesh`, or a built-in icosphere) at width x height, with the default
// light and boundary, rendered progressively until the estimated relative
// error reaches `target_error` (or `max_seconds` pass). Prints error against
// time per pass, samples/s, path vertices/s, real and null collisions, the
// medium's memory and the process's peak memory. Returns 0.
struct RenderBenchOptions {
    std::string photo;        // empty: the built-in stone
    std::string mesh;         // empty: a built-in sphere
    int resolution = 256;     // of the volume
    int width = 512, height = 512;
    double target_error = 0.05;
    double max_seconds = 600.0;
};
int run_render_benchmark(const RenderBenchOptions& options);

// How a render's true error falls with its samples: the job's render
// (`render --job`, e.g. a pipeline's report.json) as `batches` batches of
// `batch_spp` samples per pixel (app/render_job.h), independent but for the
// first flights, which stretches of one scrambled sequence per replicate
// give (render/pixel_sampler.h): they spread against each other, so the
// error across the batches reads, if anything, high. For groups of
// 1, 2, 4, … batches it prints the samples per pixel, seconds, the relative
// error measured across the groups (Film::relative_error_across, the
// truth's estimate) and the film's own estimate (the mean of the groups'),
// then the whole render's (across: the one-batch error over √batches), and both measures' log–log slopes against
// samples (the batches cost alike: against seconds too) from 64 samples
// per pixel on. Returns 0.
struct ConvergenceBenchOptions {
    std::string job;       // a job document or a report.json
    int batches = 8;
    int batch_spp = 32;
};
int run_convergence_benchmark(const ConvergenceBenchOptions& options);

// Stiff media (docs/stiff-media.md): the white furnace (albedo 1 in a unit
// sphere behind the exact boundary under a unit sky, so every pixel's truth
// is 1) at σ_t = 1, 10, …, 10⁵ per unit length, with sphere walks and with
// collision-by-collision tracking. Each case renders width² pixels for at
// most `seconds` (or `spp`) and prints its furnace mean and standard error,
// samples, microseconds per sample, set-up (the tables: seconds and MB) and
// paths cut by --max-depth. Returns 0.
struct StiffBenchOptions {
    int width = 32;
    int spp = 64;
    double seconds = 30.0;  // per case
    double max_sigma_t = 1e5;
};
int run_stiff_benchmark(const StiffBenchOptions& options);

// The paper's method beside the default on one photo and mesh (README,
// "Fidelity"): the whole pipeline twice, the paper's (per-channel matching,
// d_a = 0.1, the fBm of §4.1, k_s in 0.01 steps) and today's default, each
// with its material measured against the photo (shading divided out).
// Prints per channel A, S and D of the whole render and of the material,
// the structure distances, renders and seconds, and the ratios
// D(default) / D(paper). Writes both results under `out_dir`.
struct FidelityBenchOptions {
    std::string photo, mask, mesh;
    double photo_span = 1.0;       // Photo::span, for both methods
    std::string out_dir = "fidelity-bench";
    int resolution = 256;          // of both volumes
    int width = 512, height = 512; // of both final renders
    // Samples per pixel of both final renders and of the renders that measure
    // their material (--measure-material): the render structure distance's
    // bands under the noise (TextureSpectrum::below_noise) fall with it.
    int spp = 256;
    bool veins = false;            // the default's structure with veins (NoiseParams::veins)
    std::string structure = "photo";  // the default's --structure (parse_structure_mode)
    // Both methods with noise and render seeds 1..seeds, each pair into
    // default-seedS/ and paper-seedS/ (above 1), and D's ratio over them with
    // its standard error: one seed's pattern against the form's shading moves
    // a whole render's D by up to a factor of two.
    int seeds = 1;
    // The goal's reach by translucency (docs/design.md, "Appearance"): the
    // default's fitted volume of seed 1 as its mean medium at each of these
    // density scales, and under each one's shading the photo's own stone's D
    // and the least any material reaches, over the paper's method's D
    // (PipelineOptions::reach_densities; a shading render each). Empty: none.
    std::vector<double> densities;
};
int run_fidelity_benchmark(const FidelityBenchOptions& options);

// The pipeline options of the two methods for noise and render seed `seed`.
// The default's: the pipeline's own (the structure from the photo, joint
// matching, the sharpening the fit chooses, the contrast fit), with veins
// or another structure where asked, and on seed 1 the reach at `densities`.
// The paper's method as §4–5 give it: per-channel histogram matching of
// unsharpened levels, d_a = 0.1, §5.1's extinction, the fBm with its fixed
// frequency and amplitude ratio, and k_s stepped by 0.01 (Algorithm 2) with
// no contrast, its fitted k_s rendered as it is.
PipelineOptions default_method_options(const FidelityBenchOptions& options, int seed);
PipelineOptions paper_method_options(const FidelityBenchOptions& options, int seed);

// D(default) / D(paper) per channel over paired seeds (the same seeds for
// both methods): the ratio of the mean D's, and its standard error from the
// seeds' scatter by the delta method, the standard deviation of
// D_default − ratio·D_paper over the mean D_paper, over √n (0 for one seed).
struct SeedRatio {
    std::array<double, 3> mean_default{}, mean_paper{}, ratio{}, standard_error{};
};
SeedRatio ratio_over_seeds(const std::vector<std::array<double, 3>>& d_default,
                           const std::vector<std::array<double, 3>>& d_paper);

// One seed's whole-render D per channel: the default's and the paper's
// method's, and under the default's shading the photo's own stone's and the
// least any material reaches (fit/appearance.h, MaterialAppearance::d_stone
// and d_least; negative where not measured).
struct SeedDistances {
    // d_least_as_near: of the materials as like the stone as the default's.
    std::array<double, 3> d_default{}, d_paper{}, d_stone{}, d_least{}, d_least_as_near{};
};
// What `bench fidelity --seeds` ends with: per channel the default's D over
// the paper's (ratio_over_seeds) and each seed's; then, over the same seeds,
// the stone's and the least's D over the paper's. The goal asks the default
// for half the paper's D; where the stone itself reads above that, a render
// as near the photo as the stone misses it by the shading alone.
std::string over_seeds_summary(const std::vector<SeedDistances>& seeds);

// What `bench fidelity --densities` prints after seed 1's table: per density
// scale of the default's shading, the photo's own stone's D and the least
// any material reaches, each over the paper's method's D per channel, with
// the fitted density's own row (from the default's material measure) marked.
std::string reach_table(const std::vector<ShadingReach>& reach, const ShadingReach& fitted,
                        const std::array<double, 3>& d_paper);

}  // namespace jade
