#include "jade/app/bench.h"

#include "jade/app/pipeline.h"
#include "jade/core/error.h"
#include "jade/core/timing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace jade {

namespace {

namespace fs = std::filesystem;

// The options both methods share, with noise and render seed `seed`; their
// results go to OUT/<name>, or OUT/<name>-seed<seed> where several seeds run.
PipelineOptions common_options(const FidelityBenchOptions& b, const std::string& name, int seed) {
    PipelineOptions o;
    o.photo = b.photo;
    o.mask = b.mask;
    o.photo_span = b.photo_span;
    o.out_dir = (fs::path(b.out_dir) / (b.seeds > 1 ? name + "-seed" + std::to_string(seed) : name)).string();
    o.noise.resolution = b.resolution;
    o.noise.seed = std::uint32_t(seed);
    o.render.settings.seed = std::uint64_t(seed);
    o.render.mesh = b.mesh;
    o.render.width = b.width;
    o.render.height = b.height;
    o.render.settings.spp = b.spp;
    o.measure_material = true;
    o.progress = true;
    return o;
}

void print_row(const char* name, const std::array<double, 3>& a, const std::array<double, 3>& b,
               const char* format) {
    std::printf("  %-34s", name);
    for (const auto* v : {&a, &b}) {
        std::printf("  ");
        for (int c = 0; c < 3; ++c) std::printf(format, (*v)[c]);
    }
    std::printf("\n");
}

std::array<double, 3> ratio(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return {a[0] / b[0], a[1] / b[1], a[2] / b[2]};
}

void print_table(const PipelineResult& def, const PipelineResult& paper) {
    const MaterialAppearance& dm = *def.material;
    const MaterialAppearance& pm = *paper.material;
    // Each material's D is read over blocks where its own render's noise is
    // small beside the photo's spread (fit/appearance.h); the two compare
    // over the larger of their blocks, where both are.
    const int d_block = std::max(dm.d_block, pm.d_block);
    const std::array<double, 3>& d_def = dm.d_by_block[d_block - 1];
    const std::array<double, 3>& d_paper = pm.d_by_block[d_block - 1];
    char d_label[64];
    std::snprintf(d_label, sizeof d_label, "D material (%d px blocks)", d_block);
    std::printf("\n  %-34s  %-27s  %-27s\n", "per channel R G B", "default", "paper's method");
    print_row("A render (photo below)", def.final_look.a_render, paper.final_look.a_render, " %8.2f");
    print_row("A photo", def.final_look.a_photo, paper.final_look.a_photo, " %8.2f");
    print_row("S whole render (photo below)", def.final_look.s_render, paper.final_look.s_render, " %8.2f");
    print_row("S photo", def.final_look.s_photo, paper.final_look.s_photo, " %8.2f");
    print_row("D whole render", def.final_look.d, paper.final_look.d, " %8.4f");
    print_row("  the photo's stone, same shading", dm.d_stone, pm.d_stone, " %8.4f");
    print_row("  the least of any material", dm.d_least, pm.d_least, " %8.4f");
    print_row("  the least as like the stone", dm.d_least_as_near, pm.d_least_as_near, " %8.4f");
    print_row("S material (photo below)", dm.s_material, pm.s_material, " %8.2f");
    print_row("S photo at the material's scale", dm.s_photo, pm.s_photo, " %8.2f");
    print_row(d_label, d_def, d_paper, " %8.4f");
    // Each with its standard error from the render's noise: two renders'
    // distances closer than two or three of it are the noise's draw.
    std::printf("  %-34s  %8.3f ± %-6.3f %9s  %8.3f ± %.3f\n", "structure distance, render",
                def.final_look.structure, def.final_look.structure_error, "", paper.final_look.structure,
                paper.final_look.structure_error);
    // A band under a render's noise is the noise's draw: where most are, the
    // distance says that the render shows noise there, not how near its
    // structure is (docs/design.md, "Bands under the noise").
    std::printf("  %-34s  %5d of %-2d %15s  %5d of %-2d\n", "  bands under the noise", def.final_look.render.bands_below_noise(),
                def.final_look.render.measured_bands(), "", paper.final_look.render.bands_below_noise(),
                paper.final_look.render.measured_bands());
    std::printf("  %-34s  %8.3f %18s  %8.3f\n", "  the photo's stone, same shading", dm.structure_stone, "",
                pm.structure_stone);
    std::printf("  %-34s  %8.3f ± %-6.3f %9s  %8.3f ± %.3f\n", "structure distance, material", dm.structure,
                dm.structure_error, "", pm.structure, pm.structure_error);
    std::printf("  %-34s  %5d of %-2d %15s  %5d of %-2d\n", "  bands under the noise", dm.spectrum.bands_below_noise(),
                dm.spectrum.measured_bands(), "", pm.spectrum.bands_below_noise(), pm.spectrum.measured_bands());
    // The two materials' blocks differ in size (each render's noise sets
    // its own), so each resolves bands the other does not: compared over
    // the bands both measure as well.
    const TextureSpectrum& photo = def.final_look.photo;
    const TextureSpectrum dm_common = common_bands(dm.spectrum, pm.spectrum),
                          pm_common = common_bands(pm.spectrum, dm.spectrum);
    std::printf("  %-34s  %8.3f ± %-6.3f %9s  %8.3f ± %.3f\n", "  over the bands both measure",
                structure_distance(dm_common, photo), structure_distance_error(dm_common, photo), "",
                structure_distance(pm_common, photo), structure_distance_error(pm_common, photo));
    // Each written volume's own slices (the paper's is its fBm, unsharpened).
    std::printf("  %-34s  %8.3f %18s  %8.3f\n", "structure distance, volume slice", def.slices.distance, "",
                paper.slices.distance);
    std::printf("  %-34s  %8.3f %18s  %8.3f\n", "  slices across (normal to x, y)", def.slices_across.distance, "",
                paper.slices_across.distance);
    // A structure made for the view along z (the sweep) shows stripes
    // across it: strength far above the photo's.
    char photo_strength[32];
    std::snprintf(photo_strength, sizeof photo_strength, "(photo %.2f)", def.final_look.photo.strength);
    std::printf("  %-34s  %8.2f %18s  %8.2f\n", "  their orientation strength", def.slices_across.strength,
                photo_strength, paper.slices_across.strength);
    std::printf("  %-34s  %8d %18s  %8d\n", "fitting renders", fit_renders(def), "", fit_renders(paper));
    std::printf("  %-34s  %8.1f %18s  %8.1f\n", "seconds: fit", def.seconds_fit, "", paper.seconds_fit);
    std::printf("  %-34s  %8.1f %18s  %8.1f\n", "seconds: volume", def.seconds_volume, "", paper.seconds_volume);
    std::printf("  %-34s  %8.1f %18s  %8.1f\n", "seconds: total (less measuring)",
                def.seconds_total - def.seconds_measure, "", paper.seconds_total - paper.seconds_measure);
    std::printf("  %-34s  %-27s  %-27s\n", "fit converged", def.fit.converged ? "yes" : "no",
                paper.fit.converged ? "yes" : "no");
    const auto whole = ratio(def.final_look.d, paper.final_look.d), mat = ratio(d_def, d_paper);
    std::printf("\n  D(default) / D(paper): whole render (%.2f, %.2f, %.2f), material (%.2f, %.2f, %.2f); "
                "the goal is <= 0.5\n",
                whole[0], whole[1], whole[2], mat[0], mat[1], mat[2]);
    // What the shading alone leaves of the whole render's D: the photo's own
    // stone, lit and formed as the default's render is, against the paper's D.
    const auto stone = ratio(dm.d_stone, paper.final_look.d);
    std::printf("  the photo's own stone under the default's shading: D / D(paper) (%.2f, %.2f, %.2f)\n",
                stone[0], stone[1], stone[2]);
    // And the least any material reaches there: where it is above 0.5 no
    // material of the default's density and light meets the goal.
    const auto least = ratio(dm.d_least, paper.final_look.d);
    std::printf("  the least of any material under the default's shading: D / D(paper) (%.2f, %.2f, %.2f)\n",
                least[0], least[1], least[2]);
    // And of those whose own histogram is as near the photo's as the
    // default's material: where it is above 0.5, only a material less like
    // the stone than the default's meets the goal under that shading (in
    // the model, whose error is 2–19 % on the renders measured).
    const auto as_near = ratio(dm.d_least_as_near, paper.final_look.d);
    std::printf("  the least of any material as like the stone as the default's (D_material), same shading: "
                "D / D(paper) (%.2f, %.2f, %.2f)\n",
                as_near[0], as_near[1], as_near[2]);
    std::printf("  material blocks: %d px (%zu blocks) and %d px (%zu blocks); D's blocks %d px and %d px, "
                "compared over %d px\n",
                dm.block, dm.blocks, pm.block, pm.blocks, dm.d_block, pm.d_block, d_block);
    std::printf("  noise over D's blocks, of the photo's spread there: (%.2f, %.2f, %.2f) and (%.2f, %.2f, %.2f); "
                "the goal is <= %.2f\n",
                dm.d_noise[0] / dm.d_photo_spread[0], dm.d_noise[1] / dm.d_photo_spread[1],
                dm.d_noise[2] / dm.d_photo_spread[2], pm.d_noise[0] / pm.d_photo_spread[0],
                pm.d_noise[1] / pm.d_photo_spread[1], pm.d_noise[2] / pm.d_photo_spread[2],
                MaterialAppearance::kDNoiseShare);
}

// printf into a string.
template <typename... Args>
std::string formatted(const char* format, Args... args) {
    char line[256];
    std::snprintf(line, sizeof line, format, args...);
    return line;
}

// One line of the ratio over the seeds of `d` against the paper's D, per
// channel; "not measured" where a seed lacks `d`.
std::string ratio_line(const char* name, const std::vector<std::array<double, 3>>& d,
                       const std::vector<std::array<double, 3>>& paper) {
    std::string out = formatted("  %-42s", name);
    for (const auto& seed : d)
        for (double v : seed)
            if (!(v >= 0.0)) return out + " not measured on every seed\n";
    const SeedRatio r = ratio_over_seeds(d, paper);
    for (int c = 0; c < 3; ++c) out += formatted("  %.2f +- %.2f", r.ratio[c], r.standard_error[c]);
    return out + "\n";
}

}  // namespace

PipelineOptions default_method_options(const FidelityBenchOptions& b, int seed) {
    PipelineOptions o = common_options(b, "default", seed);
    o.noise.veins = b.veins;
    o.structure = parse_structure_mode(b.structure);
    if (seed == 1) o.reach_densities = b.densities;
    return o;
}

PipelineOptions paper_method_options(const FidelityBenchOptions& b, int seed) {
    PipelineOptions o = common_options(b, "paper", seed);
    o.structure = StructureMode::Fbm;
    o.noise.sharpen = 0.0;  // §4.2's levels as matched, whatever the fit
    o.sharpen_from_fit = false;
    o.match = MatchMode::PerChannel;
    o.optics.da = 0.1;
    o.optics.extinction = Extinction::Paper;
    o.fit.method = FitMethod::Step;
    o.final_match = false;
    return o;
}

SeedRatio ratio_over_seeds(const std::vector<std::array<double, 3>>& d_default,
                           const std::vector<std::array<double, 3>>& d_paper) {
    if (d_default.empty() || d_default.size() != d_paper.size())
        throw Error("internal: ratio_over_seeds needs one D of each method per seed");
    const double n = double(d_default.size());
    SeedRatio r;
    for (int c = 0; c < 3; ++c) {
        for (std::size_t s = 0; s < d_default.size(); ++s)
            r.mean_default[c] += d_default[s][c] / n, r.mean_paper[c] += d_paper[s][c] / n;
        r.ratio[c] = r.mean_default[c] / r.mean_paper[c];
        if (d_default.size() < 2) continue;
        double scatter = 0.0;
        for (std::size_t s = 0; s < d_default.size(); ++s) {
            const double e = d_default[s][c] - r.ratio[c] * d_paper[s][c];
            scatter += e * e / (n - 1.0);
        }
        r.standard_error[c] = std::sqrt(scatter / n) / r.mean_paper[c];
    }
    return r;
}

std::string over_seeds_summary(const std::vector<SeedDistances>& seeds) {
    std::vector<std::array<double, 3>> def, paper, stone, least, as_near;
    for (const SeedDistances& s : seeds) {
        def.push_back(s.d_default), paper.push_back(s.d_paper);
        stone.push_back(s.d_stone), least.push_back(s.d_least), as_near.push_back(s.d_least_as_near);
    }
    const SeedRatio r = ratio_over_seeds(def, paper);
    std::string out = formatted(
        "over %zu noise and render seeds, D(default) / D(paper) of the whole render, per channel R G B:\n",
        seeds.size());
    for (int c = 0; c < 3; ++c) {
        out += formatted("  %c: mean D %.4f against %.4f, ratio %.2f +- %.2f; by seed", "RGB"[c],
                         r.mean_default[c], r.mean_paper[c], r.ratio[c], r.standard_error[c]);
        for (const SeedDistances& s : seeds) out += formatted(" %.2f", s.d_default[c] / s.d_paper[c]);
        out += "\n";
    }
    out += "  the goal is <= 0.5\n";
    // What the shading alone leaves, over the same seeds: a material as near
    // the photo as the stone itself reads the first line, and none reads
    // below the second.
    out += "under the default's shading, D / D(paper) over the seeds, R G B:\n";
    out += ratio_line("the photo's own stone", stone, paper);
    out += ratio_line("the least of any material", least, paper);
    out += ratio_line("the least as like the stone as the default's", as_near, paper);
    return out;
}

std::string reach_table(const std::vector<ShadingReach>& reach, const ShadingReach& fitted,
                        const std::array<double, 3>& d_paper) {
    // The rows by density, the fitted one among them.
    std::vector<std::pair<ShadingReach, bool>> rows;
    for (const ShadingReach& r : reach) rows.push_back({r, false});
    rows.push_back({fitted, true});
    std::stable_sort(rows.begin(), rows.end(),
                     [](const auto& a, const auto& b) { return a.first.density_scale < b.first.density_scale; });
    std::string out =
        "the goal's reach by translucency: the default's fitted volume as its mean medium (its albedo held) at "
        "each density scale;\nunder its shading, D / D(paper) per channel R G B (the least above 0.5: no material "
        "there meets the goal)\n";
    out += formatted("  %-18s    %-28s%-28s%s\n", "density scale", "the photo's own stone",
                     "the least of any material", "seconds");
    auto over_paper = [&](const std::array<double, 3>& d) {
        return formatted(" %6.2f %6.2f %6.2f", d[0] / d_paper[0], d[1] / d_paper[1], d[2] / d_paper[2]);
    };
    for (const auto& [r, own] : rows)
        out += formatted("  %-18s %s       %s          %s\n",
                         formatted("%.1f%s", r.density_scale, own ? " (fitted)" : "").c_str(),
                         over_paper(r.d_stone).c_str(), over_paper(r.d_least).c_str(),
                         own ? "the measure's own" : formatted("%.1f", r.seconds).c_str());
    return out;
}

int run_fidelity_benchmark(const FidelityBenchOptions& b) {
    if (b.photo.empty() || b.mesh.empty()) throw Error("bench fidelity needs --photo and --mesh");
    if (b.seeds < 1) throw Error("bench fidelity: --seeds must be at least 1");
    if (b.spp < 1) throw Error("bench fidelity: --spp must be at least 1");
    validate_photo_span(b.photo_span);
    parse_structure_mode(b.structure);  // refused before anything is written
    validate_reach_densities(b.densities);
    std::error_code ec;
    fs::create_directories(b.out_dir, ec);
    if (ec) fail_file(b.out_dir, "cannot create the output folder: " + ec.message());
    std::printf("fidelity: %s%s on %s, volume %d^3, final renders %dx%d at %d spp, %d seed%s; results in %s/\n",
                b.photo.c_str(), photo_span_note(b.photo_span).c_str(), b.mesh.c_str(), b.resolution, b.width, b.height, b.spp, b.seeds,
                b.seeds > 1 ? "s" : "", b.out_dir.c_str());
    std::fflush(stdout);
    std::vector<SeedDistances> distances;
    for (int seed = 1; seed <= b.seeds; ++seed) {
        const PipelineResult def = run_pipeline(default_method_options(b, seed));
        const PipelineResult paper = run_pipeline(paper_method_options(b, seed));
        if (b.seeds > 1) std::printf("\nseed %d:", seed);
        print_table(def, paper);
        if (!def.reach.empty()) {
            ShadingReach fitted;
            fitted.density_scale = def.fit.density_scale;
            fitted.d_stone = def.material->d_stone;
            fitted.d_least = def.material->d_least;
            std::printf("\n%s", reach_table(def.reach, fitted, paper.final_look.d).c_str());
        }
        std::fflush(stdout);
        distances.push_back({def.final_look.d, paper.final_look.d, def.material->d_stone, def.material->d_least,
                             def.material->d_least_as_near});
    }
    if (b.seeds > 1) std::printf("\n%s", over_seeds_summary(distances).c_str());
    return 0;
}

}  // namespace jade
