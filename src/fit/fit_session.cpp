#include "jade/fit/fit_session.h"

#include "jade/core/error.h"
#include "jade/core/spectrum.h"
#include "jade/render/media/grid.h"

#include <algorithm>
#include <cmath>

namespace jade {

namespace {

// The camera at another width, same aspect and framing.
CameraParams at_width(CameraParams cam, int width) {
    const double aspect = double(cam.height) / cam.width;
    cam.width = width;
    cam.height = std::max(1, int(std::lround(width * aspect)));
    return cam;
}

FitLimits limits_for(const MaterialVolume& volume, double k_max) {
    FitLimits limits;
    limits.k_max = k_max;
    for (int c = 0; c < 3; ++c) {
        int lowest = 255;
        for (const Rgb8& lv : volume.levels) lowest = std::min(lowest, int(lv[c]));
        limits.k_min[c] = -(lowest / 256.0) * volume.optics.ds;
    }
    return limits;
}


}  // namespace

void FitOptions::validate() const {
    if (max_renders < 1) throw Error("--fit-max-renders must be at least 1");
    if (max_renders < 2 && (method == FitMethod::Bisect || exposure == 0.f))
        throw Error("--fit-max-renders must be at least 2: the fit starts with renders at both k_s bounds");
    if (!(noise > 0)) throw Error("--fit-noise must be positive");
    if (!(error > 0)) throw Error("--fit-error must be positive");
    if (spp_max < 16) throw Error("--fit-spp-max must be at least 16");
    if (!(exposure >= 0) || !std::isfinite(exposure))
        throw Error("--exposure must be positive (or 0: matched to the photo)");
    if (width < 0 || spp < 0) throw Error("--fit-width and --fit-spp must not be negative");
}

namespace {

int fitting_width(const CameraParams& camera, const FitOptions& options) {
    return options.width > 0 ? options.width : std::max(32, camera.width / 4);
}

}  // namespace

FitSession::FitSession(const MaterialVolume& volume, const Scene& scene, const CameraParams& camera,
                       const RenderSettings& settings, const Photo& photo, const FitOptions& options)
    : volume_(volume), scene_(scene), photo_(photo), options_(options),
      limits_(limits_for(volume, options.k_max)),
      camera_(at_width(camera, fitting_width(camera, options))), settings_(settings),
      photo_histogram_(RgbHistogram::of(photo.foreground_levels())), photo_spectrum_(photo_spectrum(photo)),
      pixels_per_side_(render_pixels_per_side(at_width(camera, fitting_width(camera, options)), volume.cube)) {
    options_.validate();
    settings_.time_limit = 0;
    settings_.target_error = 0;
    settings_.reference = nullptr;
    settings_.backdrop = Backdrop{nullptr, true};
    OpticalParams at_max = volume.optics;
    at_max.ks = {limits_.k_max, limits_.k_max, limits_.k_max};
    shared_majorant_ = MaterialVolumeMedium(volume, volume.cube, at_max).majorant();
}

RenderResult FitSession::render_at(const std::array<double, 3>& ks, int spp) const {
    OpticalParams optics = volume_.optics;
    optics.ks = ks;
    const MaterialVolumeMedium medium(volume_, volume_.cube, optics, shared_majorant_);
    Scene scene = scene_;
    scene.medium = &medium;
    RenderSettings settings = settings_;
    settings.spp = spp;
    return render(scene, camera_, settings);
}

// One fitting render at ks; the first chooses the sample count: doubled from
// 256 until A's standard error is below options.noise in every channel
// (measured at the photo's mean luminance) and the estimated per-pixel error
// below options.error. The light's rare paths make both estimates read low at
// a few samples, hence the start at 256.
RenderResult FitSession::fitting_render(const std::array<double, 3>& ks) {
    RenderResult r;
    if (outcome_.spp > 0) {
        r = render_at(ks, outcome_.spp);
    } else {
        constexpr int kFirstFitSpp = 256;
        for (int spp = std::min(kFirstFitSpp, options_.spp_max);; spp *= 2) {
            r = render_at(ks, spp);
            const float e = options_.exposure > 0 ? options_.exposure : matching_exposure(r.film, photo_);
            const DisplayStatistics st = display_statistics(r.film, e);
            if (st.pixels == 0)
                throw Error("the object covers no pixel of the fitting render; check the camera");
            // A's own scatter is not enough: a speckled image can have a
            // steady mean histogram that is not the converged one's.
            const bool a_steady = std::max({st.a_sigma[0], st.a_sigma[1], st.a_sigma[2]}) <= options_.noise;
            const bool pixels_converged = r.passes.back().estimated_error <= options_.error;
            if ((a_steady && pixels_converged) || spp >= options_.spp_max) {
                outcome_.spp = spp;
                outcome_.estimated_error = r.passes.back().estimated_error;
                break;
            }
        }
    }
    if (progress_) progress_->advance();
    return r;
}

// A row of fit.csv for a render at ks; returns ΔA per channel.
std::array<double, 3> FitSession::record(const std::array<double, 3>& ks, const Film& film) {
    const DisplayStatistics st = display_statistics(film, outcome_.exposure);
    const Appearance look = compare_appearance(photo_histogram_, photo_spectrum_, st, pixels_per_side_);
    FitRecord rec;
    rec.iteration = int(outcome_.records.size());
    rec.seconds = clock_.seconds();
    rec.spp = outcome_.spp;
    rec.ks = ks;
    for (int c = 0; c < 3; ++c) {
        rec.a_photo[c] = photo_histogram_.mean(c);
        rec.a_render[c] = st.a[c];
        rec.a_sigma[c] = st.a_sigma[c];
        rec.delta[c] = st.a[c] - photo_histogram_.mean(c);
        rec.distance[c] = look.d[c];
        rec.s_photo[c] = look.s_photo[c];
        rec.s_render[c] = look.s_render[c];
    }
    rec.structure = look.structure;
    outcome_.records.push_back(rec);
    return rec.delta;
}

// Renders at both bounds: they bracket every reachable channel, and they fix
// the exposure (when not given) in the middle of the range where every
// channel can reach the photo.
void FitSession::bracket(FitDriver& driver) {
    const std::array<double, 3> k_lo = limits_.k_min;
    const std::array<double, 3> k_hi{limits_.k_max, limits_.k_max, limits_.k_max};
    const RenderResult r_lo = fitting_render(k_lo);
    const RenderResult r_hi = fitting_render(k_hi);
    if (outcome_.exposure_matched)
        outcome_.exposure = float(exposure_in_reach(
            r_lo.film, r_hi.film, {photo_histogram_.mean(0), photo_histogram_.mean(1), photo_histogram_.mean(2)}));
    const std::array<double, 3> d_lo = record(k_lo, r_lo.film);
    const std::array<double, 3> d_hi = record(k_hi, r_hi.film);
    if (options_.method == FitMethod::Bisect) driver.observe_bounds(d_lo, d_hi);
}

FitOutcome FitSession::run(Progress* progress) {
    progress_ = progress;
    clock_ = Stopwatch();
    outcome_ = FitOutcome{};
    outcome_.limits = limits_;
    outcome_.spp = options_.spp;
    outcome_.width = camera_.width();
    outcome_.height = camera_.height();
    outcome_.ks_start = options_.ks_start.value_or(volume_.optics.ks);
    outcome_.exposure = options_.exposure;
    outcome_.exposure_matched = options_.exposure == 0.f;
    const bool fitting = options_.method != FitMethod::None;

    FitDriver driver(options_.method, outcome_.ks_start, limits_);
    if (options_.method == FitMethod::Bisect || (fitting && outcome_.exposure_matched)) bracket(driver);
    while (fitting && !driver.done() && int(outcome_.records.size()) < options_.max_renders) {
        const std::array<double, 3> ks = driver.k();
        const RenderResult r = fitting_render(ks);
        if (outcome_.exposure == 0.f) outcome_.exposure = matching_exposure(r.film, photo_);
        driver.observe(record(ks, r.film));
    }
    if (!fitting && outcome_.exposure == 0.f) {
        // Nothing fitted: still match the exposure, from one fitting render.
        const RenderResult r = render_at(outcome_.ks_start, outcome_.spp > 0 ? outcome_.spp : 64);
        outcome_.exposure = matching_exposure(r.film, photo_);
    }
    finish(driver);
    outcome_.seconds = clock_.seconds();
    progress_ = nullptr;
    return outcome_;
}

void FitSession::finish(const FitDriver& driver) {
    const bool fitting = options_.method != FitMethod::None;
    outcome_.converged = true;
    for (int c = 0; c < 3; ++c) {
        outcome_.ks[c] = fitting ? driver.best_k()[c] : outcome_.ks_start[c];
        outcome_.state[c] = driver.state(c);
        if (driver.state(c) == ChannelState::Unreachable) outcome_.reason[c] = driver.reason(c);
        if (driver.state(c) == ChannelState::Searching)
            outcome_.reason[c] = std::string(channel_name(c)) + ": not converged within --fit-max-renders " +
                                 std::to_string(options_.max_renders) + " renders";
        if (driver.state(c) != ChannelState::Converged) outcome_.converged = false;
    }
}

}  // namespace jade
