#pragma once
// What the pipeline writes about itself: fit.csv (one row per fitting render)
// and report.json (every parameter, timing, error and version, and the final
// render as a job document that `jaderender render --job` replays).

#include "jade/app/pipeline.h"
#include "jade/fit/display.h"
#include "jade/fit/plot.h"

#include <string>
#include <vector>

namespace jade {

// "converged", "not fitted", or why the channel stopped unconverged.
std::string channel_status(const FitOutcome& fit, int channel);

// iteration,seconds,spp, then ks, A_photo, A_render, A_sigma, dA and D per channel.
std::string fit_csv(const std::vector<FitRecord>& rows);

// convergence.png: the render's estimated relative error (and RMSE against a
// reference, when there is one) against seconds, log–log, with the 1/√t line
// through the last pass: where the error falls more slowly than 1/√t, the
// points rise above it. `what` names the render in the title (the
// pipeline's "final render", or the output file of `render`).
RgbImage8 convergence_plot(const std::vector<PassRecord>& passes, const std::string& what);

// fit.png: ΔA per channel for each fitting render (shading renders left
// out), with the tolerance ±`tolerance` as rules.
RgbImage8 fit_plot(const std::vector<FitRecord>& rows, double tolerance);

struct PipelineReport {
    const PipelineOptions& options;
    const PipelineResult& result;
    const MaterialVolume& volume;
    const Photo& photo;
    const DisplayStatistics& final_stats;
    const RenderJob& replay;     // the final render as a job
    std::string report_dir;      // the job's paths are written relative to it
};
std::string pipeline_report(const PipelineReport& report);

// What the pipeline prints when it is done (warnings to stderr, the rest to
// stdout): the fit, the brightness check, the final render against the
// photo, the seconds of each stage and the outputs.
void print_pipeline_summary(const PipelineOptions& options, const PipelineResult& result);

}  // namespace jade
