#include "jade/render/renderer.h"

#include "jade/io/atomic_file.h"
#include "jade/core/error.h"
#include "jade/core/progress.h"
#include "jade/core/timing.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <fstream>

namespace jade {

namespace {
constexpr int kTile = 16;
}

void RenderSettings::validate() const {
    if (spp < 1) throw Error("--spp must be at least 1");
    if (!(time_limit >= 0.0)) throw Error("--time must not be negative");
    if (!(target_error >= 0.0)) throw Error("--target-error must not be negative");
    integrator.validate();
}

RenderResult render(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                    Progress* progress, const std::function<void(const PassRecord&)>& on_pass) {
    settings.validate();
    if (!scene.boundary) throw Error("internal: a scene needs a boundary mesh");
    const int width = camera.width(), height = camera.height();
    RenderResult result{Film(width, height), {}, {}, 0.0, "spp"};
    Film& film = result.film;
    const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
    const Stopwatch clock;

    int done = 0;
    for (int pass = 0; done < settings.spp; ++pass) {
        // Pass sizes double (2, 2, 4, 8, ...), so the error is measured at
        // evenly spaced points on a log scale and costs little; a time budget
        // or target error shortens the pass that would overshoot it.
        int n = std::max(2, done);
        n = std::min(n, settings.spp - done);
        if (done > 0) {
            const double per_spp = clock.seconds() / done;
            if (settings.time_limit > 0.0) {
                const double left = settings.time_limit - clock.seconds();
                n = std::max(1, std::min(n, int(left / per_spp)));
            }
            const double err = result.passes.back().estimated_error;
            if (settings.target_error > 0.0 && std::isfinite(err)) {
                // Error falls as 1/sqrt(spp).
                const double need = done * (err / settings.target_error) * (err / settings.target_error);
                n = std::max(1, std::min(n, int(std::ceil(need * 1.05)) - done));
            }
        }
        const int first = done, last = done + n;

        tbb::enumerable_thread_specific<PathCounters> counters;
        tbb::parallel_for(0, tiles_x * tiles_y, [&](int tile) {
            PathCounters& local = counters.local();
            const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
            const int x1 = std::min(x0 + kTile, width), y1 = std::min(y0 + kTile, height);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const std::uint64_t pixel = std::uint64_t(y) * width + x;
                    for (int s = first; s < last; ++s) {
                        SampleStream rng(settings.seed, pixel, std::uint64_t(s));
                        const float fx = (float(x) + rng.uniform()) / float(width);
                        const float fy = (float(y) + rng.uniform()) / float(height);
                        const PathSample ps = trace_path(scene, settings.integrator, camera.origin(),
                                                         camera.direction(fx, fy), fx, fy, rng, local);
                        film.add_sample(x, y, ps.radiance, ps.hit_object);
                    }
                }
            if (progress) progress->advance(std::size_t(x1 - x0) * (y1 - y0) * n);
        });
        for (const PathCounters& c : counters) result.counters += c;
        done = last;
        film.set_spp(done);

        PassRecord rec;
        rec.pass = pass;
        rec.spp = done;
        rec.seconds = clock.seconds();
        rec.estimated_error = film.estimated_relative_error();
        if (settings.reference) {
            const ReferenceError e = compare_with_reference(film, *settings.reference);
            rec.rmse = e.rmse;
            rec.rel_mse = e.rel_mse;
        }
        result.passes.push_back(rec);
        if (on_pass) on_pass(rec);

        if (settings.target_error > 0.0 && rec.estimated_error <= settings.target_error) {
            result.stopped_by = "target error";
            break;
        }
        if (settings.time_limit > 0.0 && rec.seconds >= settings.time_limit * 0.98) {
            result.stopped_by = "time";
            break;
        }
    }
    result.seconds = clock.seconds();
    return result;
}

void write_convergence_csv(const std::string& path, const std::vector<PassRecord>& passes) {
    AtomicFile file(path);
    {
        std::ofstream out(file.temp_path());
        out << "pass,spp,seconds,estimated_rel_error,rmse,rel_mse\n";
        char line[256];
        for (const PassRecord& r : passes) {
            std::snprintf(line, sizeof line, "%d,%d,%.4f,%.6g,%s,%s\n", r.pass, r.spp, r.seconds,
                          r.estimated_error, r.rmse < 0 ? "" : std::to_string(r.rmse).c_str(),
                          r.rel_mse < 0 ? "" : std::to_string(r.rel_mse).c_str());
            out << line;
        }
        if (!out) fail_file(path, "cannot write");
    }
    file.commit();
}

}  // namespace jade
