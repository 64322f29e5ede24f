#pragma once
// What the pipeline writes about itself: fit.csv (one row per fitting render)
// and report.json (every parameter, timing, error and version, and the final
// render as a job document that `jaderender render --job` replays).

#include "jade/app/pipeline.h"
#include "jade/fit/display.h"

#include <string>
#include <vector>

namespace jade {

// "converged", "not fitted", or why the channel stopped unconverged.
std::string channel_status(const FitOutcome& fit, int channel);

// iteration,seconds,spp, then ks, A_photo, A_render, A_sigma, dA and D per channel.
std::string fit_csv(const std::vector<FitRecord>& rows);

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

}  // namespace jade
