#pragma once
// `jaderender render`: a job (app/job.h) turned into a scene (mesh, medium,
// lights, camera), rendered progressively and written out.

#include "jade/app/job.h"
#include "jade/app/render_piece.h"
#include "jade/app/scene_setup.h"
#include "jade/render/renderer.h"

#include <functional>
#include <string>
#include <vector>

namespace jade {

struct RenderJobResult {
    RenderResult render;
    std::vector<std::string> warnings;  // e.g. an open mesh
    std::vector<std::string> written;   // files, in the order written
    std::string medium_description;
    std::size_t medium_bytes = 0;
    double load_seconds = 0.0;
    float exposure = 1.f;               // the PNG's: the job's, the volume's fitted one, or 1
};

// The job's render as `batches` independent batches of `batch_spp` samples
// per pixel each: samples [j·n, (j + 1)·n) of every pixel, the pieces of one
// render of batches·n samples (merged they are bit-identical to it). The
// error measured across them has no share in the low reading of the film's
// own estimate at few samples (Film::relative_error_across; `bench
// convergence`). `on_batch(j, seconds)` after each. Nothing is written.
struct RenderBatches {
    std::vector<Film> films;
    std::vector<double> seconds;  // each batch's rendering time
    double load_seconds = 0.0;
    std::string medium_description;
};
RenderBatches render_job_batches(const RenderJob& job, int batches, int batch_spp,
                                 const std::function<void(int, double)>& on_batch = nullptr);

// Validates the job, loads everything, renders, writes the outputs (each whole
// or not at all). Throws jade::Error with one line naming the bad input.
// With a `piece`, renders only that range and writes it as a piece of the
// render (app/render_piece.h) instead of the image.
RenderJobResult run_render_job(const RenderJob& job, Progress* progress = nullptr,
                               const std::function<void(const PassRecord&)>& on_pass = nullptr,
                               const PieceRange* piece = nullptr);

}  // namespace jade
