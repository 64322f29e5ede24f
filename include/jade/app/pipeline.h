#pragma once
// The whole method in one call (paper §4–5.4, DESIGN §9–10): photo + mesh →
// material volume on the mesh's cube → k_s fitted until the render's
// histogram brightness matches the photo's → the fitted volume, the final
// render and the reports, written into one folder.

#include "jade/volume/color_match.h"
#include "jade/fit/display.h"
#include "jade/fit/driver.h"
#include "jade/volume/material_volume.h"
#include "jade/volume/noise.h"
#include "jade/app/render_job.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace jade {

struct PipelineOptions {
    std::string photo, mask;
    std::string out_dir;              // "" = "<photo name>-jaderender" in the current folder
    std::string volume;               // a jaderender .vdb to fit instead of building one from the
                                      // photo (its d_s, d_a, density scale and noise are kept)
    NoiseParams noise;
    MatchMode match = MatchMode::Joint;
    OpticalParams optics;             // for a volume built from the photo
    // Where the fit starts, and the k_s of --fit none. Default: the volume's
    // own, i.e. 0 for a new volume and the stored k_s of a given .vdb.
    std::optional<std::array<double, 3>> ks_start;
    FitMethod fit = FitMethod::Bisect;
    int fit_width = 0;                // fitting renders: 0 = a quarter of the final width
    int fit_spp = 0;                  // 0 = chosen by the first fitting render (see fit_noise)
    double fit_noise = 0.3;           // standard error of A, gray levels, the fit_spp must reach
    double fit_error = 0.4;           // and the fitting render's estimated relative error (per pixel)
    int fit_spp_max = 4096;           // the most the first fitting render doubles to
    int fit_max_renders = 24;
    FitLimits limits;                 // k_min is computed from the volume
    float exposure = 0.f;             // render → display factor before sRGB; 0 = matched at the
                                      // first fitting render (matching_exposure)
    RenderJob render;                 // mesh, boundary, lights, camera and the final render's settings
    bool progress = false;            // progress bars on stderr
};

// One fitting render: a row of fit.csv.
struct FitRecord {
    int iteration = 0;
    double seconds = 0.0;  // since fitting began
    int spp = 0;
    std::array<double, 3> ks{}, a_photo{}, a_render{}, a_sigma{}, delta{}, distance{};
};

struct PipelineResult {
    std::string out_dir;
    std::vector<FitRecord> fit;
    std::array<double, 3> ks{};                 // fitted (the best found per channel)
    std::array<std::string, 3> channel_status;  // "converged", or why not
    bool converged = false;
    float exposure = 1.f;                       // the exposure used (given or matched)
    RenderResult final_render;
    std::vector<std::string> warnings;
    std::vector<std::string> written;
    double seconds_photo = 0, seconds_volume = 0, seconds_fit = 0, seconds_render = 0,
           seconds_write = 0, seconds_total = 0;
};

PipelineResult run_pipeline(const PipelineOptions& options);

// The folder a photo's results go to by default: "<stem>-jaderender".
std::string default_out_dir(const std::string& photo);

}  // namespace jade
