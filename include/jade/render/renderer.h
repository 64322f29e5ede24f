#pragma once
// Progressive rendering: passes of camera samples over image tiles in
// parallel (TBB), each followed by a measurement of the image's error, until
// the sample count, the time budget or the target error is reached.
//
// Each camera sample's random numbers are keyed by (seed, pixel, sample
// index) and each pixel's samples are added in index order by one thread, so
// an image is bit-identical for a seed whatever the thread count.

#include "jade/core/image.h"
#include "jade/render/camera.h"
#include "jade/render/film.h"
#include "jade/render/integrator.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace jade {

class Progress;

// What a camera ray that leaves without meeting the object sees.
struct Backdrop {
    const Background* image = nullptr;  // stretched over the film; else the environment
    bool transparent = false;           // nothing (the film's alpha is the coverage)
};

struct RenderSettings {
    int spp = 256;              // stop after this many samples per pixel
    double time_limit = 0.0;    // seconds; 0 = none
    double target_error = 0.0;  // estimated relative error to stop at; 0 = none
    std::uint64_t seed = 1;
    IntegratorSettings integrator;
    Backdrop backdrop;
    const ImageF32* reference = nullptr;  // for RMSE after each pass
    void validate() const;
};

// One row of convergence.csv: the image's error against run time.
struct PassRecord {
    int pass = 0;
    int spp = 0;                  // samples per pixel so far: the fewest any pixel holds
    double mean_spp = 0.0;        // and on average (more than spp when a time budget cut the pass)
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
    // Of those, the integrator's set-up (a stiff medium's sphere exit
    // tables), and the tables' memory.
    double setup_seconds = 0.0;
    std::size_t sphere_exit_bytes = 0;
    std::string stopped_by;  // "spp", "time" or "target error"
    // Pixels that hold no sample: a time budget that ran out during the
    // first pass leaves them black (reported, never hidden).
    std::size_t unsampled_pixels = 0;
};

// Samples [first, last) of each pixel, and a rectangle of pixels [x0, x1) × [y0, y1).
struct SampleRange {
    int first = 0, last = 0;
};
struct PixelBounds {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The pixels whose camera rays can meet a surface held in the convex hull of
// `hull` (Boundary::hull_points: a mesh's vertices, a sphere's box): the
// film's rectangle about the points' projections (a ray meets the hull only
// within the projection of its corners), widened by a pixel on every side
// against rounding; the whole film when a point lies on or behind the
// camera's plane, empty when there is no point. A pixel outside it sees only
// the backdrop, which a render adds without tracing.
PixelBounds pixels_seeing(const PinholeCamera& camera, const std::vector<glm::vec3>& hull);

// One piece of a render: the samples `samples` of the pixels in `bounds`, in
// a film of the whole image's size (other pixels hold no sample). Pieces
// merged with Film::merge are bit-identical to one render of all their
// samples (the random numbers are keyed by seed, pixel and sample index, and
// the film's sums are exact).
Film render_pass(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                 SampleRange samples, PixelBounds bounds, PathCounters* counters = nullptr,
                 Progress* progress = nullptr);

// What a camera sample sees behind the object: the backdrop's radiance times
// the weight the path carried out of the scene (zero unless it left without
// interacting).
Spectrum backdrop(const Scene& scene, const Backdrop& backdrop, const PathSample& ps, float fx,
                  float fy);

// Progressive rendering: passes of samples over the whole image until the
// sample count, the time budget or the target error is reached.
RenderResult render(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                    Progress* progress = nullptr,
                    const std::function<void(const PassRecord&)>& on_pass = nullptr);

// The same render, able to pause: run_to(n) renders on until n samples per
// pixel (or until the settings' own stop), and a later call carries on from
// there. The integrator is built once, for settings.spp (its light guide's
// size follows the whole render's samples). The samples are keyed by index
// and each pixel's are added in index order, so a render paused and carried
// on is bit-identical to render()'s; its passes and seconds count every
// part, not the time between parts. What it serves: a look at the first
// samples before the rest is worth making (the pipeline's brightness check
// reads A at the final size from the final render's first quarter, and the
// render carries on where the check keeps k_s). The scene must outlive it.
class ProgressiveRender {
public:
    ProgressiveRender(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings);
    // With `object_alone` (a film of the render's size), this part's
    // samples go there too, less what the backdrop gave them: bit for bit
    // the same samples with a transparent backdrop (the object alone, as
    // the fit measures it; docs/design.md, "The backdrop").
    void run_to(int spp, Progress* progress = nullptr,
                const std::function<void(const PassRecord&)>& on_pass = nullptr, Film* object_alone = nullptr);
    int samples() const { return done_; }
    // The settings' sample count reached, or a time budget or target error met.
    bool finished() const { return stopped_ || done_ >= settings_.spp; }
    const RenderResult& result() const { return result_; }
    RenderResult take() && { return std::move(result_); }

private:
    const Scene& scene_;
    PinholeCamera camera_;
    RenderSettings settings_;
    RenderResult result_;  // before integrator_: its set-up's seconds are written there
    Integrator integrator_;
    int done_ = 0;
    bool stopped_ = false;
};

// A render of settings.spp samples per pixel (no time budget or target
// error) kept as two independent halves: each pixel's replicates 0–1 and
// 2–3 (render/pixel_sampler.h), equal in size to within a turn of the
// heroes. Samples [0, n/2) and [n/2, n) would not be independent: they
// share each replicate's sequence.
// Merged (Film::merge) they are bit-identical to render()'s film; their
// difference holds the render's noise and nothing of the image, which is
// how a statistic of the image is freed of the noise's share (the fit's
// S_material, fit/display.h). The integrator is set up once for both.
struct SplitFilms {
    Film first, second;
    // render_quarters only: the quarters, replicates 0 … 3 in order, the
    // first two making `first`, as images (RGBA, alpha = coverage; a film
    // would take 13 times the memory): the same statistic at half the
    // samples, from which its bias from the noise is extrapolated away.
    std::vector<ImageF32> quarters;
    Film merged() const;
};
SplitFilms render_halves(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                         PathCounters* counters = nullptr, Progress* progress = nullptr);
// The same halves, bit for bit, and their quarters (both: settings.spp ≥
// 3 kReplicates, a turn in every replicate).
SplitFilms render_quarters(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                           PathCounters* counters = nullptr, Progress* progress = nullptr);

// pass,spp,seconds,estimated_rel_error,rmse,rel_mse,mean_spp — written whole or not at all.
void write_convergence_csv(const std::string& path, const std::vector<PassRecord>& passes);

// A pass's samples per pixel for the console: "256 spp", or after a pass cut
// short by a time budget "at least 256 spp (318.4 on average)".
std::string format_spp(const PassRecord& pass);

}  // namespace jade
