#include "jade/app/bench.h"

#include "jade/app/pipeline.h"
#include "jade/core/error.h"
#include "jade/core/timing.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

namespace jade {

namespace {

namespace fs = std::filesystem;

PipelineOptions common_options(const FidelityBenchOptions& b, const std::string& name) {
    PipelineOptions o;
    o.photo = b.photo;
    o.mask = b.mask;
    o.out_dir = (fs::path(b.out_dir) / name).string();
    o.noise.resolution = b.resolution;
    o.render.mesh = b.mesh;
    o.render.width = b.width;
    o.render.height = b.height;
    o.measure_material = true;
    o.progress = true;
    return o;
}

// The paper's method as §4–5 give it: per-channel histogram matching, d_a =
// 0.1, §5.1's extinction, the fBm with its fixed frequency and amplitude ratio, and k_s stepped
// by 0.01 (Algorithm 2) with no contrast, its fitted k_s rendered as it is.
PipelineOptions paper_options(const FidelityBenchOptions& b) {
    PipelineOptions o = common_options(b, "paper");
    o.structure = StructureMode::Fbm;
    o.match = MatchMode::PerChannel;
    o.optics.da = 0.1;
    o.optics.extinction = Extinction::Paper;
    o.fit.method = FitMethod::Step;
    o.final_match = false;
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
    print_row("S material (photo below)", dm.s_material, pm.s_material, " %8.2f");
    print_row("S photo at the material's scale", dm.s_photo, pm.s_photo, " %8.2f");
    print_row(d_label, d_def, d_paper, " %8.4f");
    std::printf("  %-34s  %8.3f %18s  %8.3f\n", "structure distance, render", def.final_look.structure, "",
                paper.final_look.structure);
    std::printf("  %-34s  %8.3f %18s  %8.3f\n", "  the photo's stone, same shading", dm.structure_stone, "",
                pm.structure_stone);
    std::printf("  %-34s  %8.3f %18s  %8.3f\n", "structure distance, material", dm.structure, "",
                pm.structure);
    // The two materials' blocks differ in size (each render's noise sets
    // its own), so each resolves bands the other does not: compared over
    // the bands both measure as well.
    const TextureSpectrum& photo = def.final_look.photo;
    std::printf("  %-34s  %8.3f %18s  %8.3f\n", "  over the bands both measure",
                structure_distance(common_bands(dm.spectrum, pm.spectrum), photo), "",
                structure_distance(common_bands(pm.spectrum, dm.spectrum), photo));
    if (def.structure_estimated)
        std::printf("  %-34s  %8.3f %18s  %8.3f\n", "structure distance, volume slice", def.structure.chosen.distance,
                    "", def.structure.paper.distance);
    std::printf("  %-34s  %8d %18s  %8d\n", "fitting renders", def.fit.renders, "", paper.fit.renders);
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

}  // namespace

int run_fidelity_benchmark(const FidelityBenchOptions& b) {
    if (b.photo.empty() || b.mesh.empty()) throw Error("bench fidelity needs --photo and --mesh");
    std::error_code ec;
    fs::create_directories(b.out_dir, ec);
    if (ec) fail_file(b.out_dir, "cannot create the output folder: " + ec.message());
    std::printf("fidelity: %s on %s, volume %d^3, final renders %dx%d; results in %s/\n", b.photo.c_str(),
                b.mesh.c_str(), b.resolution, b.width, b.height, b.out_dir.c_str());
    std::fflush(stdout);
    PipelineOptions defaults = common_options(b, "default");
    defaults.noise.veins = b.veins;
    const PipelineResult def = run_pipeline(defaults);
    const PipelineResult paper = run_pipeline(paper_options(b));
    print_table(def, paper);
    return 0;
}

}  // namespace jade
