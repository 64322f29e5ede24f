#include "jade/app/report.h"

#include "jade/app/job.h"
#include "jade/core/timing.h"
#include "jade/io/atomic_file.h"
#include "jade/io/vdb_io.h"

#include <OpenImageIO/oiioversion.h>
#include <embree3/rtcore_config.h>
#include <nlohmann/json.hpp>
#include <oneapi/tbb/version.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace jade {

std::string channel_status(const FitOutcome& fit, int c) {
    if (fit.state[c] == ChannelState::Converged)
        return fit.records.empty() ? "not fitted" : "converged";
    return fit.reason[c];
}

std::string fit_csv(const std::vector<FitRecord>& rows) {
    std::string s = "iteration,seconds,spp";
    const char* ch[3] = {"r", "g", "b"};
    for (const char* name : {"ks", "contrast", "A_photo", "A_render", "A_sigma", "dA", "D", "S_photo", "S_render",
                             "S_photo_scaled", "S_material", "S_material_noise", "A_final_size"})
        for (const char* c : ch) s += std::string(",") + name + "_" + c;
    s += ",density_scale,structure,structure_error,orientation_photo,orientation_render,strength_photo,"
         "strength_render,shading,from_final_size,sharpen\n";
    char buf[160];
    for (const FitRecord& r : rows) {
        std::snprintf(buf, sizeof buf, "%d,%.3f,%d", r.iteration, r.seconds, r.spp);
        s += buf;
        for (const auto* arr : {&r.ks, &r.contrast, &r.a_photo, &r.a_render, &r.a_sigma, &r.delta, &r.distance,
                                &r.s_photo, &r.s_render, &r.s_photo_scaled, &r.s_material, &r.s_material_noise,
                                &r.a_final_size})
            for (double v : *arr) {
                std::snprintf(buf, sizeof buf, ",%.6g", v);
                s += buf;
            }
        std::snprintf(buf, sizeof buf, ",%.6g,%.6g,%.3g,%.4g,%.4g,%.4g,%.4g,%d,%d,%.6g\n", r.density_scale,
                      r.structure, r.structure_error, r.orientation_photo, r.orientation_render, r.strength_photo,
                      r.strength_render, r.shading ? 1 : 0, r.from_final_size ? 1 : 0, r.sharpen);
        s += buf;
    }
    return s;
}

RgbImage8 convergence_plot(const std::vector<PassRecord>& passes, const std::string& what) {
    PlotSpec spec;
    spec.title = what + ": estimated relative error against time";
    spec.x_label = "seconds";
    spec.y_label = "error";
    spec.log_x = spec.log_y = true;
    PlotSeries est{{}, {}, Rgb8{255, 190, 70}, false, "estimated relative error"};
    PlotSeries rmse{{}, {}, Rgb8{90, 200, 255}, false, "RMSE vs reference"};
    for (const PassRecord& p : passes) {
        est.x.push_back(p.seconds);
        est.y.push_back(p.estimated_error);
        if (p.rmse >= 0) {
            rmse.x.push_back(p.seconds);
            rmse.y.push_back(p.rmse);
        }
    }
    // 1/sqrt(t) through the last pass with a finite error.
    PlotSeries ideal{{}, {}, Rgb8{170, 170, 170}, true, "1/sqrt(t) through the last pass"};
    for (auto it = passes.rbegin(); it != passes.rend(); ++it)
        if (std::isfinite(it->estimated_error) && it->seconds > 0) {
            for (const PassRecord& p : passes)
                if (p.seconds > 0) {
                    ideal.x.push_back(p.seconds);
                    ideal.y.push_back(it->estimated_error * std::sqrt(it->seconds / p.seconds));
                }
            break;
        }
    spec.series = {ideal, est};
    if (!rmse.x.empty()) spec.series.push_back(rmse);
    return line_plot(spec);
}

RgbImage8 fit_plot(const std::vector<FitRecord>& rows, double tolerance) {
    PlotSpec spec;
    spec.title = "fit: dA = A(render) - A(photo) per row of fit.csv";
    spec.x_label = "row of fit.csv";
    spec.y_label = "dA (levels)";
    spec.y_rules = {-tolerance, tolerance};
    const Rgb8 colours[3] = {Rgb8{255, 70, 70}, Rgb8{70, 230, 70}, Rgb8{90, 130, 255}};
    const char* names[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) {
        PlotSeries s{{}, {}, colours[c], false, names[c]};
        int n = 0;
        for (const FitRecord& r : rows) {
            if (r.shading) continue;
            s.x.push_back(++n);
            s.y.push_back(r.delta[c]);
        }
        spec.series.push_back(s);
    }
    return line_plot(spec);
}

namespace {

// The structure distance (texture_spectrum.h) of the written volume's own
// slices to the photo; and where the structure was estimated, the
// estimate's and the paper's fBm's as the estimate measured them.
nlohmann::json structure_json(const PipelineResult& res) {
    const auto measures = [](const StructureFit& s) {
        return nlohmann::json{
            {"distance", s.distance}, {"strength", s.strength}, {"coherence", s.coherence}, {"defects", s.defects}};
    };
    nlohmann::json j = {{"slices", measures(res.slices)}, {"slices_across", measures(res.slices_across)}};
    if (!res.structure_estimated) return j;
    const StructureEstimate& e = res.structure;
    j.update({{"seconds", res.seconds_structure},  {"photo_orientation", e.photo.orientation},
              {"photo_strength", e.photo.strength}, {"photo_coherence", e.photo.coherence},
              {"distance", e.chosen.distance},      {"strength", e.chosen.strength},
              {"coherence", e.chosen.coherence},    {"paper_fbm_distance", e.paper.distance},
              {"defects", e.chosen.defects},        {"photo_defects", e.photo.defects},
              {"paper_fbm_strength", e.paper.strength}});
    return j;
}

// A texture spectrum as its measured bands: the lower edge of each band
// (cycles per cube side), its share of the variance and that share's
// standard error from the noise, and whether it is below the noise, so that
// two spectra in one report can be plotted against each other.
nlohmann::json spectrum_json(const TextureSpectrum& s) {
    std::vector<double> cycles, share, error;
    std::vector<bool> below;
    for (int b = 0; b < TextureSpectrum::kBands; ++b)
        if (s.power[b] >= 0.0) {
            cycles.push_back(TextureSpectrum::band_low(b));
            share.push_back(s.power[b]);
            error.push_back(s.error[b]);
            below.push_back(s.below_noise[b]);
        }
    return {{"cycles_per_side", cycles}, {"power_share", share},   {"power_share_error", error},
            {"below_noise", below},      {"square_pixels", s.square}};
}

// What a person compares (fit/appearance.h): per channel A, S and D, and the
// structure of the render's object pixels against the photo's.
nlohmann::json appearance_json(const Appearance& look) {
    return {{"A_photo", look.a_photo},
            {"A_render", look.a_render},
            {"S_photo", look.s_photo},
            {"S_render", look.s_render},
            {"D", look.d},
            {"structure_distance", look.structure},
            {"structure_distance_error", look.structure_error},
            {"photo_orientation", look.photo.orientation},
            {"photo_strength", look.photo.strength},
            {"photo_coherence", look.photo.coherence},
            {"photo_defects", look.photo.defects},
            {"render_orientation", look.render.orientation},
            {"render_strength", look.render.strength},
            {"render_coherence", look.render.coherence},
            {"render_defects", look.render.defects},
            {"render_square_pixels", look.render.square},
            {"photo_spectrum", spectrum_json(look.photo)},
            {"render_spectrum", spectrum_json(look.render)}};
}

// The programs and libraries that made the outputs.
nlohmann::json versions_json() {
    return {{"jaderender", JADE_VERSION},      {"openvdb", openvdb_version()},
            {"openimageio", OIIO_VERSION_STRING}, {"embree", RTC_VERSION_STRING},
            {"tbb", TBB_VERSION_STRING}};
}

nlohmann::json volume_json(const PipelineOptions& o, const MaterialVolume& volume) {
    return {{"from", o.volume.empty() ? "built from the photo" : o.volume},
            {"resolution", volume.resolution}, {"octaves", volume.noise.octaves},
            {"k", volume.noise.k}, {"seed", volume.noise.seed}, {"structure", to_string(volume.structure)},
            {"frequency", volume.noise.frequency}, {"stretch", volume.noise.stretch},
            {"angle", volume.noise.angle}, {"bands", volume.noise.bands}, {"warp", volume.noise.warp},
            {"fold", volume.noise.fold},
            {"veins", volume.noise.veins}, {"vein_frequency", volume.noise.vein_frequency},
            {"vein_width", volume.noise.vein_width}, {"layers", volume.noise.layers},
            {"sharpen", volume.noise.sharpen}, {"sharpen_radius", volume.noise.sharpen_radius},
            {"exemplar", volume.noise.exemplar}, {"exemplar_wander", volume.noise.exemplar_wander},
            {"sharpen_clipped", volume.sharpen_clipped},
            {"match", to_string(volume.match)},
            {"extinction", to_string(volume.optics.extinction)},
            {"ds", volume.optics.ds}, {"da", volume.optics.da},
            {"density_scale", volume.optics.density_scale}, {"contrast", volume.optics.contrast},
            {"mean_level", volume.optics.mean_level},
            {"cube_min", volume.cube.min}, {"cube_side", volume.cube.side},
            {"vdb_up_axis", o.vdb_z_up ? "z" : "y"}, {"vdb_color_grid", o.vdb_color_name}};
}

// ΔA and D of the fitting render at the chosen k_s, contrast and density
// scale (the best per channel may come from different renders), and under
// --fit contrast ΔA at the final render's size, which it judged too.
void add_final_residuals(const FitOutcome& fit, nlohmann::json& out) {
    std::array<double, 3> delta{}, dist{}, at_final_size{-1e300, -1e300, -1e300};
    for (int c = 0; c < 3; ++c) {
        double best = 1e300;
        for (const FitRecord& r : fit.records)
            if (!r.shading && r.ks[c] == fit.ks[c] && r.contrast[c] == fit.contrast[c] &&
                r.density_scale == fit.density_scale && std::abs(r.delta[c]) < best) {
                best = std::abs(r.delta[c]);
                delta[c] = r.delta[c];
                dist[c] = r.distance[c];
                at_final_size[c] = r.a_final_size[c] >= 0.0 ? r.a_final_size[c] - r.a_photo[c] : -1e300;
            }
    }
    const bool have_final_size =
        std::all_of(at_final_size.begin(), at_final_size.end(), [](double d) { return d > -1e299; });
    out["final_delta_A"] = delta;
    out["final_D"] = dist;
    if (have_final_size) out["final_delta_A_final_size"] = at_final_size;
}

nlohmann::json fit_json(const PipelineOptions& o, const FitOutcome& fit) {
    std::array<std::string, 3> status;
    for (int c = 0; c < 3; ++c) status[c] = channel_status(fit, c);
    nlohmann::json j = {
        {"method", to_string(o.fit.method)}, {"renders", fit.renders},
        {"max_renders", o.fit.max_renders}, {"spp", fit.spp}, {"width", fit.width},
        {"height", fit.height}, {"noise_target", o.fit.noise}, {"error_target", o.fit.error},
        {"estimated_relative_error", fit.estimated_error}, {"exposure", fit.exposure},
        {"exposure_matched", fit.exposure_matched}, {"tolerance", fit.limits.tolerance},
        {"step", fit.limits.step}, {"ks_start", fit.ks_start}, {"ks_min", fit.limits.k_min},
        {"ks_max", fit.limits.k_max}, {"ks", fit.ks}, {"contrast_start", fit.contrast_start},
        {"contrast", fit.contrast}, {"density_scale_start", fit.density_scale_start},
        {"density_scale", fit.density_scale}, {"density_scale_max", fit.density_scale_max},
        {"converged", fit.converged}, {"stopped_at_density_ceiling", fit.stopped_at_density_ceiling},
        {"stopped_at_first_rise", fit.stopped_at_first_rise},
        {"channel_status", status}};
    if (o.fit.method == FitMethod::Contrast)
        j["S"] = {{"tolerance", o.fit.s_tolerance}, {"photo_at_material_scale", fit.s_photo},
                  {"material", fit.s_material}, {"material_block", fit.material_block},
                  {"spp", fit.spread_spp}, {"spp_raised_from", fit.spread_spp_raised_from},
                  {"spp_advised", fit.spread_spp_advised},
                  {"contrast_fitted", fit.contrast_fitted}};
    if (!fit.records.empty()) add_final_residuals(fit, j);
    return j;
}

// The sharper stone's fit (PipelineOptions::sharpen_from_fit), where it was
// considered: the sharpening chosen and why, and the fit not kept in full.
nlohmann::json sharper_json(const PipelineOptions& o, const SharperStone& sh) {
    nlohmann::json j = {{"first", sh.first}, {"chosen", sh.sharper}, {"why", sh.why}, {"tried", sh.tried},
                        {"kept", sh.kept}};
    if (!sh.tried) return j;
    j["seconds"] = sh.seconds;
    j["from_stop"] = sh.from_stop;
    j[sh.kept ? "first_fit" : "sharper_fit"] = fit_json(o, sh.other);
    if (sh.stopped) j["first_fit_stopped"] = fit_json(o, *sh.stopped);
    return j;
}

nlohmann::json final_render_json(const PipelineReport& in) {
    const RenderResult& render = in.result.final_render;
    const PassRecord& last = render.passes.back();
    return {{"width", in.replay.width}, {"height", in.replay.height},
            {"spp", last.spp}, {"mean_spp", last.mean_spp}, {"seconds", render.seconds},
            {"estimated_relative_error", last.estimated_error},
            {"stopped_by", render.stopped_by},
            {"capped_paths", render.counters.capped_paths},
            {"sphere_walks", render.counters.sphere_walks},
            {"A_render", in.final_stats.a}};
}

nlohmann::json brightness_check_json(const BrightnessCheck& b) {
    return {{"A_full_size_from", b.from_fit ? "fit renders" : b.from_final_render ? "final render" : "check renders"},
            {"spp", b.spp}, {"seconds", b.seconds}, {"A_size_change", b.size_change},
            {"white_share", b.white_share}, {"near_white_by_noise", b.noise_clipped},
            {"delta_A", b.delta}, {"fitting_renders", b.renders},
            {"delta_A_expected", b.expected},
            {"ks_before", b.ks_before}, {"ks", b.ks_after}, {"corrected", b.corrected()}};
}

// The material with the shading divided out (fit/appearance.h).
nlohmann::json material_json(const MaterialAppearance& m) {
    return {{"S_material", m.s_material}, {"S_material_noise", m.s_noise}, {"S_photo", m.s_photo},
            {"D", m.d}, {"D_stone_shaded", m.d_stone}, {"D_least_any_material", m.d_least},
            {"D_least_as_near_material", m.d_least_as_near}, {"structure_distance", m.structure},
            {"structure_distance_error", m.structure_error},
            {"structure_distance_stone_shaded", m.structure_stone}, {"spectrum", spectrum_json(m.spectrum)},
            {"block_pixels", m.block}, {"blocks", m.blocks}, {"D_block_pixels", m.d_block},
            {"D_by_block", m.d_by_block}, {"D_noise", m.d_noise}, {"D_photo_spread", m.d_photo_spread}};
}

nlohmann::json preview_json(const GltfPreviewMaterial& pv) {
    return {{"file", "preview.glb"},
            {"base_color", pv.base_color},
            {"transmission", pv.transmission},
            {"attenuation_color", pv.attenuation_color},
            {"attenuation_distance", pv.attenuation_distance},
            {"thickness", pv.thickness},
            {"ior", pv.ior},
            {"mean_sigma_s", pv.sigma_s},
            {"mean_sigma_a", pv.sigma_a},
            {"slab_reflectance", pv.slab_R},
            {"slab_transmittance", pv.slab_T}};
}

nlohmann::json seconds_json(const PipelineResult& res) {
    return {{"inputs", res.seconds_photo}, {"volume", res.seconds_volume}, {"fit", res.seconds_fit},
            {"brightness_check", res.seconds_check}, {"final_render", res.seconds_render},
            {"measure_material", res.seconds_measure}, {"write", res.seconds_write},
            {"total", res.seconds_total}};
}

}  // namespace

std::string pipeline_report(const PipelineReport& in) {
    using nlohmann::json;
    const PipelineOptions& o = in.options;
    const PipelineResult& res = in.result;
    json j;
    j["versions"] = versions_json();
    j["inputs"] = {{"photo", o.photo}, {"mask", o.mask}, {"photo_span", in.photo.span}, {"mesh", o.render.mesh},
                   {"foreground_pixels", in.photo.foreground_count()}};
    // The manifest: report.json is written last, so the set it names (each
    // file with its size) is complete when it exists (docs/robustness.md).
    json outputs = json::object();
    for (const std::string& path : res.written)
        outputs[std::filesystem::path(path).filename().string()] = file_size(path);
    j["outputs"] = outputs;
    j["volume"] = volume_json(o, in.volume);
    j["structure"] = structure_json(res);
    j["fit"] = fit_json(o, res.fit);
    if (res.sharper) j["sharpening"] = sharper_json(o, *res.sharper);
    j["final_render"] = final_render_json(in);
    if (const auto& b = res.brightness_check) j["brightness_check"] = brightness_check_json(*b);
    j["appearance"] = appearance_json(res.final_look);
    if (res.material) j["appearance"]["material"] = material_json(*res.material);
    // The goal's reach at other translucencies (PipelineOptions::reach_densities).
    for (const ShadingReach& r : res.reach)
        j["appearance"]["reach_by_density"].push_back({{"density_scale", r.density_scale},
                                                       {"D_stone_shaded", r.d_stone},
                                                       {"D_least_any_material", r.d_least},
                                                       {"seconds", r.seconds}});
    j["preview"] = preview_json(res.preview);
    // The final render as a job document: `jaderender render --job report.json` replays it.
    j["job"] = json::parse(job_json(in.replay, in.report_dir));
    j["seconds"] = seconds_json(res);
    j["peak_memory_bytes"] = peak_rss_bytes();
    j["warnings"] = res.warnings;
    return j.dump(2) + "\n";
}

namespace {

// The sharper stone on the console: why it was not tried, or its fit's
// outcome beside the other one.
void print_sharper_summary(const SharperStone& sh, const FitOutcome& kept) {
    if (!sh.tried) {
        std::printf("  sharpening %g: %s\n", sh.first, sh.why.c_str());
        return;
    }
    const FitOutcome& sharper = sh.kept ? kept : sh.other;
    if (sh.from_stop) {
        const FitOutcome& first = sh.kept ? sh.other : *sh.stopped;
        // The sharper stone's levels and fit, a resumption left out.
        const double seconds = sh.kept ? sh.seconds : sh.resumed_began - first.seconds;
        std::printf("  sharpening %g (%s): the first fit (sharpening %g) stopped there after %d renders, and the "
                    "sharper stone's fit took its search on in %d renders, %.1f s: %s",
                    sh.sharper, sh.why.c_str(), sh.first, first.renders, sharper.renders, seconds,
                    sh.kept ? "converged, kept\n" : "NOT converged; ");
        if (!sh.kept)
            std::printf("the first stone's fit went on from its stop in %d renders, its volume kept\n", kept.renders);
        return;
    }
    const FitOutcome& first = sh.kept ? sh.other : kept;
    std::printf("  sharpening %g (%s): fitted from the first fit's outcome (sharpening %g) in %d renders, %.1f s: "
                "%s; the first fit: %d renders, contrast (%.3f, %.3f, %.3f), density scale %.4g\n",
                sh.sharper, sh.why.c_str(), sh.first, sharper.renders, sh.seconds,
                sh.kept ? "converged, kept" : "NOT converged, the first fit's volume kept", first.renders,
                first.contrast[0], first.contrast[1], first.contrast[2], first.density_scale);
}

// The fit's outcome on the console: warnings, k_s, contrast and density
// scale, the last fitting render's A and the brightness check.
void print_fit_summary(const PipelineOptions& o, const PipelineResult& r) {
    for (const auto& w : r.warnings) std::fprintf(stderr, "jaderender: warning: %s\n", w.c_str());
    const FitOutcome& fit = r.fit;
    for (int c = 0; c < 3; ++c)
        if (fit.state[c] != ChannelState::Converged)
            std::fprintf(stderr, "jaderender: warning: fit: %s\n", fit.reason[c].c_str());
    const FitRecord* best = fit.records.empty() ? nullptr : &fit.records.back();
    const bool contrast = o.fit.method == FitMethod::Contrast;
    const bool all_s = fit.contrast_fitted == std::array<bool, 3>{true, true, true};
    const bool no_s = fit.contrast_fitted == std::array<bool, 3>{false, false, false};
    char goal[160];
    if (!contrast || no_s)
        std::snprintf(goal, sizeof goal, "|dA| < %g in every channel", fit.limits.tolerance);
    else if (all_s)
        std::snprintf(goal, sizeof goal, "|dA| < %g and |dS| < %g in every channel", fit.limits.tolerance,
                      o.fit.s_tolerance);
    else
        std::snprintf(goal, sizeof goal, "|dA| < %g in every channel, |dS| < %g where the contrast was fitted",
                      fit.limits.tolerance, o.fit.s_tolerance);
    // Every fit's renders where the sharper stone was fitted too.
    const int renders = fit_renders(r);
    std::printf("fit (%s): %d renders at %d spp in %.1f s; exposure %.4f; k_s = (%.4f, %.4f, %.4f); contrast "
                "(%.3f, %.3f, %.3f); %s\n",
                to_string(o.fit.method), renders, fit.spp, r.seconds_fit, fit.exposure, fit.ks[0], fit.ks[1],
                fit.ks[2], fit.contrast[0], fit.contrast[1], fit.contrast[2],
                fit.converged ? goal : "NOT converged (see the warnings)");
    if (contrast)
        std::printf("  S_material (the render's spread less its shading and noise): (%.1f, %.1f, %.1f); the photo's "
                    "S at the same scale (%d px blocks of the final render): (%.1f, %.1f, %.1f); density scale %.4g "
                    "(from %.4g)\n",
                    fit.s_material[0], fit.s_material[1], fit.s_material[2], fit.material_block, fit.s_photo[0],
                    fit.s_photo[1], fit.s_photo[2], fit.density_scale,
                    fit_legs(r).front().fit->density_scale_start);
    if (r.sharper) print_sharper_summary(*r.sharper, fit);
    if (contrast && fit.spread_spp_raised_from > 0)
        std::printf("  S_material hid in the noise of the first step's renders at %d spp; read at %d spp, as the fit "
                    "raised --fit-spread-spp 0 (%d times, where that many show it; give a count to keep it)\n",
                    fit.spread_spp_raised_from, fit.spread_spp, kMaxSpreadSppGain);
    if (contrast && !all_s) {
        std::string hidden;
        int count = 0;
        for (int c = 0; c < 3; ++c)
            if (!fit.contrast_fitted[c]) hidden += std::string(count++ ? ", " : "") + channel_name(c);
        std::printf("  contrast not fitted in %s: %s S hides in the noise of the fit's renders at %d spp",
                    hidden.c_str(), count > 1 ? "their" : "its", fit.spread_spp);
        if (fit.spread_spp_advised > 0)
            std::printf("; run again with --fit-spread-spp %d to fit it (each contrast step then takes about %d "
                        "times as long)",
                        fit.spread_spp_advised, std::max(1, fit.spread_spp_advised / std::max(1, fit.spread_spp)));
        std::printf("\n");
    }
    if (best)
        std::printf("  last fitting render: A photo (%.2f, %.2f, %.2f), render (%.2f, %.2f, %.2f), "
                    "dA (%+.2f, %+.2f, %+.2f) +- (%.2f, %.2f, %.2f)\n",
                    best->a_photo[0], best->a_photo[1], best->a_photo[2], best->a_render[0], best->a_render[1],
                    best->a_render[2], best->delta[0], best->delta[1], best->delta[2], best->a_sigma[0],
                    best->a_sigma[1], best->a_sigma[2]);
    if (const auto& b = r.brightness_check) {
        const std::string spp = std::to_string(b->spp);
        const std::string source = b->from_fit            ? "the fit's renders at " + spp + " spp"
                                   : b->from_final_render ? "the final render's first " + spp + " spp"
                                                          : "the check's renders at " + spp + " spp";
        std::printf("brightness check in %.1f s, A at full size from %s: A at full size less A "
                    "at the fitting size (%+.2f, %+.2f, %+.2f), so dA (%+.2f, %+.2f, %+.2f) expected",
                    b->seconds, source.c_str(), b->size_change[0], b->size_change[1], b->size_change[2], b->delta[0],
                    b->delta[1], b->delta[2]);
        if (b->corrected())
            std::printf("; k_s corrected to (%.4f, %.4f, %.4f) (fitting renders: %d), dA (%+.2f, %+.2f, %+.2f) "
                        "expected\n",
                        b->ks_after[0], b->ks_after[1], b->ks_after[2], b->renders, b->expected[0], b->expected[1],
                        b->expected[2]);
        else
            std::printf("; k_s kept\n");
    }
}

// After a structure distance: how many of the noisy spectrum's bands lie
// under its noise (TextureSpectrum::below_noise), where any do.
std::string under_noise(const TextureSpectrum& s) {
    const int below = s.bands_below_noise();
    if (below == 0) return "";
    return " (" + std::to_string(below) + " of " + std::to_string(s.measured_bands()) + " bands under the noise)";
}

// The final render's outcome on the console: its error, how it compares with
// the photo, the stages' seconds and the files written.
void print_render_summary(const PipelineResult& r) {
    const PassRecord& last = r.final_render.passes.back();
    std::printf("final render: %s in %.1f s, estimated relative error %.4f", format_spp(last).c_str(),
                r.final_render.seconds, last.estimated_error);
    const std::optional<BrightnessCheck>& check = r.brightness_check;
    if (check && check->from_final_render && !check->corrected())
        std::printf(" (its first %d spp made during the brightness check)", check->spp);
    std::printf("\n");
    const Appearance& look = r.final_look;
    std::printf("final render against the photo: A (%.1f, %.1f, %.1f) / (%.1f, %.1f, %.1f), S (%.1f, %.1f, %.1f) / "
                "(%.1f, %.1f, %.1f), D (%.4f, %.4f, %.4f), structure distance %.3f ± %.3f%s\n",
                look.a_render[0], look.a_render[1], look.a_render[2], look.a_photo[0], look.a_photo[1], look.a_photo[2],
                look.s_render[0], look.s_render[1], look.s_render[2], look.s_photo[0], look.s_photo[1],
                look.s_photo[2], look.d[0], look.d[1], look.d[2], look.structure, look.structure_error,
                under_noise(look.render).c_str());
    if (r.material)
        std::printf("material against the photo (shading divided out, %d px blocks): S (%.1f, %.1f, %.1f) / "
                    "(%.1f, %.1f, %.1f), D (%.4f, %.4f, %.4f) over %d px blocks (noise %.1f, %.1f, %.1f levels; "
                    "the photo's spread there %.1f, %.1f, %.1f), structure distance %.3f ± %.3f%s; its two renders and the comparison %.1f s; "
                    "the photo's own stone under the render's shading: D (%.4f, %.4f, %.4f), structure distance "
                    "%.3f; the least D of any material under it (%.4f, %.4f, %.4f), of any as like the stone as this one "
                    "(%.4f, %.4f, %.4f)\n",
                    r.material->block, r.material->s_material[0], r.material->s_material[1],
                    r.material->s_material[2], r.material->s_photo[0], r.material->s_photo[1],
                    r.material->s_photo[2], r.material->d[0], r.material->d[1], r.material->d[2], r.material->d_block,
                    r.material->d_noise[0], r.material->d_noise[1], r.material->d_noise[2],
                    r.material->d_photo_spread[0], r.material->d_photo_spread[1], r.material->d_photo_spread[2],
                    r.material->structure, r.material->structure_error, under_noise(r.material->spectrum).c_str(),
                    r.seconds_measure,
                    r.material->d_stone[0], r.material->d_stone[1],
                    r.material->d_stone[2], r.material->structure_stone, r.material->d_least[0],
                    r.material->d_least[1], r.material->d_least[2], r.material->d_least_as_near[0],
                    r.material->d_least_as_near[1], r.material->d_least_as_near[2]);
    if (r.structure_estimated)
        std::printf("structure from the photo%s in %.2f s: frequency %.2f, k %.2f, stretch %.2f, angle %.1f, "
                    "bands %.1f, warp %.2f%s; slice-to-photo structure distance %.3f (the paper's fBm: %.3f)\n",
                    photo_span_note(r.structure.photo_span).c_str(), r.seconds_structure,
                    r.structure.chosen.noise.frequency, r.structure.chosen.noise.k,
                    r.structure.chosen.noise.stretch, r.structure.chosen.noise.angle, r.structure.chosen.noise.bands,
                    r.structure.chosen.noise.warp, r.structure.chosen.noise.family_suffix().c_str(),
                    r.structure.chosen.distance,
                    r.structure.paper.distance);
    std::printf("the volume's slices against the photo: structure distance %.3f, orientation strength %.2f, "
                "coherence %.2f, orientation defects %.3f\n",
                r.slices.distance, r.slices.strength, r.slices.coherence, r.slices.defects);
    std::printf("the volume's slices across (normal to x and y): structure distance %.3f, orientation strength %.2f, "
                "coherence %.2f, orientation defects %.3f\n",
                r.slices_across.distance, r.slices_across.strength, r.slices_across.coherence,
                r.slices_across.defects);
    std::printf("seconds: inputs %.2f, volume %.2f, fit %.2f, brightness check %.2f, final render %.2f, writing %.2f; "
                "total %.1f; peak memory %s\n",
                r.seconds_photo, r.seconds_volume, r.seconds_fit, r.seconds_check, r.seconds_render, r.seconds_write,
                r.seconds_total, format_megabytes(double(peak_rss_bytes())).c_str());
    std::printf("outputs in %s/:", r.out_dir.c_str());
    for (const auto& f : r.written) std::printf(" %s", std::filesystem::path(f).filename().c_str());
    std::printf("\n");
}

}  // namespace

void print_pipeline_summary(const PipelineOptions& options, const PipelineResult& result) {
    print_fit_summary(options, result);
    print_render_summary(result);
}

}  // namespace jade
