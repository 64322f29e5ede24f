#include "jade/render/renderer.h"

#include "jade/render/light_guide.h"
#include "jade/render/pixel_sampler.h"

#include "jade/io/atomic_file.h"
#include "jade/core/error.h"
#include "jade/core/progress.h"
#include "jade/core/timing.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

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

namespace {

// A time by which a pass must stop, even half done (a render's --time).
struct Deadline {
    const Stopwatch* clock = nullptr;
    double seconds = 0.0;
    bool passed() const { return clock && clock->seconds() >= seconds; }
};

// The films a render's samples go to: one, or a group of the pixel's
// replicates each (render/pixel_sampler.h), which are independent.
struct FilmsByReplicate {
    std::vector<Film*> films;  // replicate r goes to films[r · size / kReplicates]
    Film& of(int replicate) const { return *films[std::size_t(replicate) * films.size() / kReplicates]; }
    // Where given, every sample also goes here less what the backdrop gave
    // it: the object alone, as a transparent backdrop leaves it.
    Film* object_alone = nullptr;
};

// A camera sample's film position in pixel (x, y), from its place u in
// the pixel (render/pixel_sampler.h).
glm::vec2 film_position(const PinholeCamera& camera, int x, int y, const std::array<float, 2>& u) {
    const float fx = (float(x) + u[0]) / float(camera.width());
    const float fy = (float(y) + u[1]) / float(camera.height());
    return {fx, fy};
}

// Samples [samples.first, samples.last) of pixel (x, y), in index order.
// Their camera rays leave one point in nearly one direction: each packet of
// Boundary::kPacket is traced at once, and every path goes on alone from
// its first hit. A sample's film position is the pixel's
// (PixelSampler::film_numbers).
void add_pixel_samples(const Scene& scene, const Integrator& integrator,
                       const PinholeCamera& camera, const RenderSettings& settings,
                       SampleRange samples, int x, int y, const FilmsByReplicate& out, PathCounters& counters) {
    constexpr int kPacket = Boundary::kPacket;
    const std::uint64_t pixel = std::uint64_t(y) * camera.width() + x;
    const PixelSampler sampler(settings.seed, pixel);
    // The three samples of a turn of the heroes share their first numbers.
    std::uint64_t numbers_turn = ~std::uint64_t(0);
    FirstNumbers numbers;
    for (int first = samples.first; first < samples.last; first += kPacket) {
        const int n = std::min(kPacket, samples.last - first);
        std::array<SampleStream, kPacket> rng;
        std::array<glm::vec2, kPacket> film_at;
        std::array<glm::vec3, kPacket> direction;
        for (int i = 0; i < n; ++i) {
            rng[std::size_t(i)] = SampleStream(settings.seed, pixel, std::uint64_t(first + i));
            film_at[std::size_t(i)] =
                film_position(camera, x, y, sampler.film_numbers(std::uint64_t(first + i)));
            direction[std::size_t(i)] = camera.direction(film_at[std::size_t(i)].x, film_at[std::size_t(i)].y);
        }
        std::array<std::optional<SurfaceHit>, kPacket> hit;
        scene.boundary->intersect_packet(camera.origin(), direction.data(), n, hit.data());
        for (int i = 0; i < n; ++i) {
            const auto k = std::size_t(i);
            const auto sample = std::uint64_t(first + i);
            const int hero = sampler.hero(sample);
            if (sample / 3 != numbers_turn) {
                numbers_turn = sample / 3;
                numbers = sampler.first_numbers(sample);
            }
            const PathSample ps =
                integrator.trace(camera.origin(), direction[k], hit[k], hero, numbers, rng[k], counters);
            const Spectrum behind = backdrop(scene, settings.backdrop, ps, film_at[k].x, film_at[k].y);
            const int replicate = sample_replicate(sample);
            out.of(replicate).add_sample(x, y, ps.radiance + behind, ps.hit_object, hero, replicate);
            if (out.object_alone) out.object_alone->add_sample(x, y, ps.radiance, ps.hit_object, hero, replicate);
        }
    }
}

// The same samples of a pixel none of whose camera rays can meet the object
// (pixels_seeing): each is what a traced one would be bit for bit, a path
// that leaves at once with weight 1 along its camera ray, but nothing is
// traced; a backdrop that is the same in every direction is looked up once
// and added to each stratum and replicate in one step. On reference scene A,
// where 61 % of the pixels show only the backdrop, tracing their samples
// took about a tenth of the render's time.
void add_backdrop_samples(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                          SampleRange samples, int x, int y, const FilmsByReplicate& out) {
    const std::uint64_t pixel = std::uint64_t(y) * camera.width() + x;
    const PixelSampler sampler(settings.seed, pixel);
    PathSample ps;
    ps.backdrop_weight = Spectrum(1.f);
    if (settings.backdrop.transparent || (!settings.backdrop.image && !scene.environment.is_image())) {
        ps.backdrop_direction = camera.direction(0.5f, 0.5f);
        const Spectrum value = backdrop(scene, settings.backdrop, ps, 0.5f, 0.5f);
        std::array<std::array<std::uint32_t, Film::kStrata>, kReplicates> counts{};
        for (int k = samples.first; k < samples.last; ++k) {
            const auto sample = std::uint64_t(k);
            ++counts[std::size_t(sample_replicate(sample))][std::size_t(sampler.hero(sample))];
        }
        for (int r = 0; r < kReplicates; ++r) {
            out.of(r).add_samples(x, y, value, counts[std::size_t(r)], r);
            if (out.object_alone) out.object_alone->add_samples(x, y, Spectrum(0.f), counts[std::size_t(r)], r);
        }
        return;
    }
    for (int k = samples.first; k < samples.last; ++k) {
        const auto sample = std::uint64_t(k);
        const glm::vec2 at = film_position(camera, x, y, sampler.film_numbers(sample));
        ps.backdrop_direction = camera.direction(at.x, at.y);
        const int replicate = sample_replicate(sample);
        out.of(replicate).add_sample(x, y, backdrop(scene, settings.backdrop, ps, at.x, at.y), false,
                                     sampler.hero(sample), replicate);
        if (out.object_alone) out.object_alone->add_sample(x, y, Spectrum(0.f), false, sampler.hero(sample), replicate);
    }
}

// Samples [samples.first, samples.last) of every pixel in `bounds`, added to
// `film` in index order per pixel, tiles in parallel. A sample's random
// numbers are keyed by (seed, pixel, sample index) and the film's sums are
// exact, so the result does not depend on threads, tiles or how a render is
// split into passes or pieces.
void add_samples(const Scene& scene, const Integrator& integrator, const PinholeCamera& camera,
                 const RenderSettings& settings, SampleRange samples, PixelBounds bounds,
                 const FilmsByReplicate& out, PathCounters& counters, Progress* progress, Deadline deadline = {}) {
    const int tiles_x = (bounds.x1 - bounds.x0 + kTile - 1) / kTile;
    const int tiles_y = (bounds.y1 - bounds.y0 + kTile - 1) / kTile;
    const PixelBounds seen = pixels_seeing(camera, scene.boundary->hull_points());
    tbb::enumerable_thread_specific<PathCounters> local_counters;
    tbb::parallel_for(0, tiles_x * tiles_y, [&](int tile) {
        PathCounters& local = local_counters.local();
        const int x0 = bounds.x0 + (tile % tiles_x) * kTile, y0 = bounds.y0 + (tile / tiles_x) * kTile;
        const int x1 = std::min(x0 + kTile, bounds.x1), y1 = std::min(y0 + kTile, bounds.y1);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                // Past the deadline the rest of the pass is left out: each
                // pixel's mean stays an unbiased estimate of its own samples.
                if (deadline.passed()) return;
                if (x >= seen.x0 && x < seen.x1 && y >= seen.y0 && y < seen.y1)
                    add_pixel_samples(scene, integrator, camera, settings, samples, x, y, out, local);
                else
                    add_backdrop_samples(scene, camera, settings, samples, x, y, out);
            }
        if (progress) progress->advance(std::size_t(x1 - x0) * (y1 - y0) * (samples.last - samples.first));
    });
    for (const PathCounters& c : local_counters) counters += c;
}

// Samples in the next pass: passes double (1, 1, 2, 4, 8, ...), so the error
// is measured at evenly spaced points on a log scale and costs little; the
// first pass gives every pixel one sample as soon as possible (under a time
// budget, an image before anything else); a time budget or target error
// shortens the pass that would overshoot it.
int next_pass_size(const RenderSettings& settings, int done, double seconds, double error) {
    int n = std::min(std::max(1, done), settings.spp - done);
    if (done == 0) return n;
    const double per_spp = seconds / done;
    if (settings.time_limit > 0.0) {
        const double left = settings.time_limit - seconds;
        n = std::max(1, std::min(n, int(left / per_spp)));
    }
    if (settings.target_error > 0.0 && std::isfinite(error)) {
        // Error falls as 1/sqrt(spp).
        const double need = done * (error / settings.target_error) * (error / settings.target_error);
        n = std::max(1, std::min(n, int(std::ceil(need * 1.05)) - done));
    }
    return n;
}

// The integrator of a render of the whole camera at settings.spp. The light
// guide's rays follow the render's camera samples, not a piece's, so every
// piece of a split render builds the same guide.
Integrator make_integrator(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings) {
    IntegratorSettings integrator = settings.integrator;
    integrator.light_guide_photons =
        light_guide_photons(double(camera.width()) * double(camera.height()) * double(settings.spp));
    return Integrator(scene, integrator, settings.seed);
}

}  // namespace

PixelBounds pixels_seeing(const PinholeCamera& camera, const std::vector<glm::vec3>& hull) {
    const PixelBounds film{0, 0, camera.width(), camera.height()};
    glm::vec2 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (const glm::vec3& p : hull) {
        const std::optional<glm::vec2> f = camera.film_point(p);
        if (!f || !std::isfinite(f->x) || !std::isfinite(f->y)) return film;
        lo = glm::min(lo, *f);
        hi = glm::max(hi, *f);
    }
    if (!(lo.x <= hi.x && lo.y <= hi.y)) return {};  // no vertex: nothing to see
    // In pixels, widened by one on every side; far off the film, clamped
    // before the conversion to int.
    const auto pixel = [](float f, int size) {
        return int(std::floor(std::clamp(f * float(size), -2.f, float(size) + 2.f)));
    };
    PixelBounds b;
    b.x0 = std::clamp(pixel(lo.x, camera.width()) - 1, 0, camera.width());
    b.x1 = std::clamp(pixel(hi.x, camera.width()) + 2, b.x0, camera.width());
    b.y0 = std::clamp(pixel(lo.y, camera.height()) - 1, 0, camera.height());
    b.y1 = std::clamp(pixel(hi.y, camera.height()) + 2, b.y0, camera.height());
    return b;
}

Spectrum backdrop(const Scene& scene, const Backdrop& backdrop, const PathSample& ps, float fx,
                  float fy) {
    if (backdrop.transparent || ps.backdrop_weight == Spectrum(0.f)) return Spectrum(0.f);
    return ps.backdrop_weight * (backdrop.image ? backdrop.image->at(fx, fy)
                                                : scene.environment.radiance_toward(ps.backdrop_direction));
}

Film render_pass(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                 SampleRange samples, PixelBounds bounds, PathCounters* counters, Progress* progress) {
    settings.validate();
    if (samples.first < 0 || samples.last < samples.first)
        throw Error("the sample range must be first:last with 0 <= first <= last");
    if (bounds.x0 < 0 || bounds.y0 < 0 || bounds.x1 > camera.width() ||
        bounds.y1 > camera.height() || bounds.x0 > bounds.x1 || bounds.y0 > bounds.y1)
        throw Error("the pixel bounds lie outside the image");
    const Integrator integrator = make_integrator(scene, camera, settings);
    Film film(camera.width(), camera.height());
    PathCounters local;
    add_samples(scene, integrator, camera, settings, samples, bounds, {{&film}}, local, progress);
    if (counters) *counters += local;
    return film;
}

namespace {
Integrator built_integrator(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings) {
    settings.validate();
    return make_integrator(scene, camera, settings);
}
}  // namespace

// The clock includes the integrator's set-up (a stiff medium's sphere exit
// tables take seconds): error against time is the user's time.
ProgressiveRender::ProgressiveRender(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings)
    : scene_(scene), camera_(camera), settings_(settings), integrator_([&] {
          const Stopwatch clock;
          Integrator integrator = built_integrator(scene, camera, settings);
          result_.setup_seconds = clock.seconds();
          return integrator;
      }()) {
    result_.film = Film(camera.width(), camera.height());
    result_.stopped_by = "spp";
    result_.seconds = result_.setup_seconds;
    result_.sphere_exit_bytes = integrator_.sphere_exit_bytes();
}

void ProgressiveRender::run_to(int spp, Progress* progress, const std::function<void(const PassRecord&)>& on_pass,
                               Film* object_alone) {
    if (object_alone && (object_alone->width() != camera_.width() || object_alone->height() != camera_.height()))
        throw Error("internal: the film of the object alone is not the render's size");
    const Stopwatch clock;
    const double before = result_.seconds;  // the parts before this one
    const auto elapsed = [&] { return before + clock.seconds(); };
    const int last = std::min(spp, settings_.spp);
    const PixelBounds whole{0, 0, camera_.width(), camera_.height()};
    while (!stopped_ && done_ < last) {
        const double error = done_ > 0 ? result_.passes.back().estimated_error : 0.0;
        const int n = std::min(next_pass_size(settings_, done_, elapsed(), error), last - done_);
        // A time budget also stops a pass under way, the first included:
        // one pass can take far longer than the ones before it foretold (a
        // stiff voxel that few paths reach). Pixels the first pass did not
        // reach stay black and are counted.
        Deadline deadline;
        if (settings_.time_limit > 0.0) deadline = {&clock, settings_.time_limit - before};
        FilmsByReplicate out{{&result_.film}};
        out.object_alone = object_alone;
        add_samples(scene_, integrator_, camera_, settings_, {done_, done_ + n}, whole, out, result_.counters,
                    progress, deadline);
        const bool cut = deadline.passed();
        done_ = cut ? result_.film.fewest_samples() : done_ + n;

        PassRecord rec;
        rec.pass = int(result_.passes.size());
        rec.spp = done_;
        rec.mean_spp = cut ? result_.film.mean_samples() : double(done_);
        rec.seconds = elapsed();
        rec.estimated_error = result_.film.estimated_relative_error();
        if (settings_.reference) {
            const ReferenceError e = compare_with_reference(result_.film, *settings_.reference);
            rec.rmse = e.rmse;
            rec.rel_mse = e.rel_mse;
        }
        result_.passes.push_back(rec);
        if (on_pass) on_pass(rec);

        if (settings_.target_error > 0.0 && rec.estimated_error <= settings_.target_error) {
            result_.stopped_by = "target error";
            stopped_ = true;
        } else if (cut || (settings_.time_limit > 0.0 && rec.seconds >= settings_.time_limit * 0.98)) {
            result_.stopped_by = "time";
            stopped_ = true;
        }
    }
    result_.seconds = elapsed();
    result_.unsampled_pixels = 0;
    for (int y = 0; y < camera_.height(); ++y)
        for (int x = 0; x < camera_.width(); ++x) result_.unsampled_pixels += result_.film.samples(x, y) == 0 ? 1 : 0;
}

RenderResult render(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                    Progress* progress, const std::function<void(const PassRecord&)>& on_pass) {
    ProgressiveRender r(scene, camera, settings);
    r.run_to(settings.spp, progress, on_pass);
    return std::move(r).take();
}

Film SplitFilms::merged() const {
    Film film = first;
    film.merge(second);
    return film;
}

namespace {

// settings.spp samples per pixel in 2 · `parts` groups of the pixels'
// replicates (render/pixel_sampler.h), independent of one another; with
// two parts each group is kept as an image too, and the halves are
// groups 0–1 and 2–3.
SplitFilms render_split(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                        int parts, PathCounters* counters, Progress* progress) {
    static_assert(kReplicates % 4 == 0, "halves and quarters are groups of whole replicates");
    settings.validate();
    if (settings.spp < 3 * kReplicates)
        throw Error("internal: a render in independent parts needs a turn of the heroes in every replicate (" +
                    std::to_string(3 * kReplicates) + " samples per pixel)");
    const Integrator integrator = make_integrator(scene, camera, settings);
    const PixelBounds whole{0, 0, camera.width(), camera.height()};
    PathCounters local;
    std::vector<Film> groups(std::size_t(2 * parts), Film(camera.width(), camera.height()));
    FilmsByReplicate out;
    for (Film& g : groups) out.films.push_back(&g);
    add_samples(scene, integrator, camera, settings, {0, settings.spp}, whole, out, local, progress);
    if (counters) *counters += local;
    if (parts == 1) return SplitFilms{std::move(groups[0]), std::move(groups[1]), {}};
    SplitFilms films;
    for (const Film& g : groups) films.quarters.push_back(ImageF32{camera.width(), camera.height(), 4, g.rgba(true)});
    groups[0].merge(groups[1]);
    groups[2].merge(groups[3]);
    films.first = std::move(groups[0]);
    films.second = std::move(groups[2]);
    return films;
}

}  // namespace

SplitFilms render_halves(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                         PathCounters* counters, Progress* progress) {
    return render_split(scene, camera, settings, 1, counters, progress);
}

SplitFilms render_quarters(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                           PathCounters* counters, Progress* progress) {
    return render_split(scene, camera, settings, 2, counters, progress);
}

void write_convergence_csv(const std::string& path, const std::vector<PassRecord>& passes) {
    std::string text = "pass,spp,seconds,estimated_rel_error,rmse,rel_mse,mean_spp\n";
    char line[256];
    for (const PassRecord& r : passes) {
        std::snprintf(line, sizeof line, "%d,%d,%.4f,%.6g,%s,%s,%.2f\n", r.pass, r.spp, r.seconds,
                      r.estimated_error, r.rmse < 0 ? "" : std::to_string(r.rmse).c_str(),
                      r.rel_mse < 0 ? "" : std::to_string(r.rel_mse).c_str(), r.mean_spp);
        text += line;
    }
    write_text_file(path, text);
}

std::string format_spp(const PassRecord& pass) {
    char buf[64];
    // Two decimals of the mean are what convergence.csv keeps.
    if (pass.mean_spp > double(pass.spp) + 0.005)
        std::snprintf(buf, sizeof buf, "at least %d spp (%.1f on average)", pass.spp, pass.mean_spp);
    else
        std::snprintf(buf, sizeof buf, "%d spp", pass.spp);
    return buf;
}

}  // namespace jade
