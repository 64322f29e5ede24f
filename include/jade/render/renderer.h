#pragma once
// Progressive rendering: passes of camera samples over image tiles in
// parallel (TBB), each followed by a measurement of the image's error, until
// the sample count, the time budget or the target error is reached.
//
// Each camera sample's random numbers are keyed by (seed, pixel, sample
// index) and each pixel's samples are added in index order by one thread, so
// an image is bit-identical for a seed whatever the thread count.

#include "jade/render/camera.h"
#include "jade/render/film.h"
#include "jade/render/integrator.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace jade {

class Progress;

struct RenderSettings {
    int spp = 256;              // stop after this many samples per pixel
    double time_limit = 0.0;    // seconds; 0 = none
    double target_error = 0.0;  // estimated relative error to stop at; 0 = none
    std::uint64_t seed = 1;
    IntegratorSettings integrator;
    const ImageF32* reference = nullptr;  // for RMSE after each pass
    void validate() const;
};

// One row of convergence.csv: the image's error against run time.
struct PassRecord {
    int pass = 0;
    int spp = 0;                  // total samples per pixel so far
    double seconds = 0.0;         // since the render began
    double estimated_error = 0.0; // Film::estimated_relative_error (NaN before 2 spp)
    double rmse = -1.0;           // against the reference, -1 without one
    double rel_mse = -1.0;
};

struct RenderResult {
    Film film;
    std::vector<PassRecord> passes;
    PathCounters counters;
    double seconds = 0.0;
    std::string stopped_by;  // "spp", "time" or "target error"
};

RenderResult render(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                    Progress* progress = nullptr,
                    const std::function<void(const PassRecord&)>& on_pass = nullptr);

// pass,spp,seconds,estimated_rel_error,rmse,rel_mse — written whole or not at all.
void write_convergence_csv(const std::string& path, const std::vector<PassRecord>& passes);

}  // namespace jade
