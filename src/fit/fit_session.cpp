#include "jade/fit/fit_session.h"

#include "jade/fit/broyden.h"

#include "jade/core/error.h"
#include "jade/core/spectrum.h"
#include "jade/render/light_estimator.h"
#include "jade/render/light_guide.h"
#include "jade/render/media/grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace jade {

namespace {

// The camera at another width, same aspect and framing.
CameraParams at_width(CameraParams cam, int width) {
    const double aspect = double(cam.height) / cam.width;
    cam.width = width;
    cam.height = std::max(1, int(std::lround(width * aspect)));
    return cam;
}

std::array<int, 3> lowest_levels(const MaterialVolume& volume) {
    std::array<int, 3> lowest{255, 255, 255};
    for (const Rgb8& lv : volume.levels)
        for (int c = 0; c < 3; ++c) lowest[c] = std::min(lowest[c], int(lv[c]));
    return lowest;
}

// The smallest k_s keeps σ_s = v'·d_s + k_s >= 0 in the lowest voxel.
double k_min_for(OpticalParams optics, int lowest_level, int c, double contrast) {
    optics.contrast[c] = contrast;
    return -contrasted_level(lowest_level, c, optics) * optics.ds;
}

FitLimits limits_for(const OpticalParams& optics, const std::array<int, 3>& lowest,
                     const std::array<double, 3>& contrast, double k_max) {
    FitLimits limits;
    limits.k_max = k_max;
    for (int c = 0; c < 3; ++c) limits.k_min[c] = k_min_for(optics, lowest[c], c, contrast[c]);
    return limits;
}

}  // namespace

void FitOptions::validate() const {
    if (!(k_max > 0.0) || !std::isfinite(k_max)) throw Error("--ks-max must be positive and finite");
    if (max_renders < 1) throw Error("--fit-max-renders must be at least 1");
    if (max_renders < 2 && (bisects(method) || exposure == 0.f))
        throw Error("--fit-max-renders must be at least 2: the fit starts with renders at both k_s bounds");
    if (method == FitMethod::Contrast && max_renders < kMinContrastRenders)
        throw Error("--fit-max-renders must be at least " + std::to_string(kMinContrastRenders) +
                    " with --fit contrast: 2 at the k_s bounds, then steps of a render and its shading render (and "
                    "a render at the fitting size when S is measured at the final one)");
    if (!(s_tolerance > 0)) throw Error("the S tolerance must be positive");
    if (contrast_start)
        for (double g : *contrast_start)
            if (!(g >= 0.0 && g <= kMaxContrast))
                throw Error("--contrast must be between 0 and " + std::to_string(int(kMaxContrast)));
    if (!(noise > 0)) throw Error("--fit-noise must be positive");
    if (!(error > 0)) throw Error("--fit-error must be positive");
    if (spp_max < 16) throw Error("--fit-spp-max must be at least 16");
    if (!(exposure >= 0) || !std::isfinite(exposure))
        throw Error("--exposure must be positive (or 0: matched to the photo)");
    if (width < 0 || spp < 0) throw Error("--fit-width and --fit-spp must not be negative");
    if (start && method != FitMethod::Contrast)
        throw Error("a fit starts from another's outcome only under --fit contrast");
    if (spread_spp != 0 && spread_spp < kMinSpreadSpp)
        throw Error("--fit-spread-spp must be 0 (as many samples per image as a fitting render) or at least " +
                    std::to_string(kMinSpreadSpp));
}

namespace {


// The share of a channel's object pixels at one end of the 8-bit range
// above which the channel counts as clipped.
constexpr double kClippedShare = 0.5;

// Per channel, whether most of a render's object pixels sit at level 0 or
// 255: its A is then only a bound.
std::array<bool, 3> clipped(const FitRecord& rec) {
    std::array<bool, 3> out{};
    for (int c = 0; c < 3; ++c) out[c] = std::max(rec.at_black[c], rec.at_white[c]) > kClippedShare;
    return out;
}

int fitting_width(const CameraParams& camera, const FitOptions& options) {
    return options.width > 0 ? options.width : std::max(32, camera.width / 4);
}

// The whole factor by which the final camera is larger than the fitting
// camera in both sides, else 0 (box_factor_).
int box_factor(const PinholeCamera& final_camera, const PinholeCamera& fitting) {
    const int f = final_camera.width() / fitting.width();
    const bool whole = f > 1 && final_camera.width() == f * fitting.width() &&
                       final_camera.height() == f * fitting.height();
    return whole ? f : 0;
}

}  // namespace

FitSession::FitSession(const MaterialVolume& volume, const Scene& scene, const CameraParams& camera,
                       const RenderSettings& settings, const Photo& photo, const FitOptions& options)
    : volume_(volume), scene_(scene), photo_(photo), options_(options), lowest_level_(lowest_levels(volume)),
      level_histograms_(level_histograms(volume.levels)), optics_(volume.optics),
      limits_(limits_for(volume.optics, lowest_level_,
                         options.start ? options.start->contrast : options.contrast_start.value_or(volume.optics.contrast),
                         options.k_max)),
      camera_(at_width(camera, fitting_width(camera, options))), settings_(settings),
      photo_histogram_(RgbHistogram::of(photo.foreground_levels())), photo_spectrum_(photo_spectrum(photo)),
      pixels_per_side_(render_pixels_per_side(at_width(camera, fitting_width(camera, options)), volume.cube)),
      spread_at_final_size_(fitting_width(camera, options) < camera.width),
      final_camera_(camera),
      spread_pixels_per_side_(spread_at_final_size_ ? render_pixels_per_side(camera, volume.cube) : pixels_per_side_),
      box_factor_(box_factor(final_camera_, camera_)) {
    options_.validate();
    if (options_.start) {  // that fit's sample counts, found or raised there
        if (options_.start->spp > 0) options_.spp = options_.start->spp;
        if (options_.start->spread_spp > 0) options_.spread_spp = options_.start->spread_spp;
    }
    settings_.time_limit = 0;
    settings_.target_error = 0;
    settings_.reference = nullptr;
    settings_.backdrop = Backdrop{nullptr, true};
    set_density_scale(volume.optics.density_scale);
}

void FitSession::set_density_scale(double density_scale) {
    density_scale_ = density_scale;
    OpticalParams at_max = optics_;
    at_max.density_scale = density_scale;
    at_max.ks = {limits_.k_max, limits_.k_max, limits_.k_max};
    // Clipped at every level: the largest σ_t any contrast the fit tries gives.
    at_max.contrast = {kMaxContrast, kMaxContrast, kMaxContrast};
    shared_majorant_ = MaterialVolumeMedium(volume_, volume_.cube, at_max).majorant();
}

// Calls how(scene, camera, settings) with the scene holding the volume at
// ks, contrast and the current density scale (under the shared majorant),
// and the fitting renders' settings at spp samples per pixel, with the
// light guide a render through `camera` traces (light_guide, below).
template <class How>
auto FitSession::with_medium(const PinholeCamera& camera, const std::array<double, 3>& ks,
                             const std::array<double, 3>& contrast, int spp, How how) const {
    OpticalParams optics = optics_;
    optics.ks = ks;
    optics.contrast = contrast;
    optics.density_scale = density_scale_;
    const MaterialVolumeMedium medium(volume_, volume_.cube, optics, shared_majorant_);
    Scene scene = scene_;
    scene.medium = &medium;
    RenderSettings settings = settings_;
    settings.spp = spp;
    settings.integrator.built_light_guide = light_guide(scene, camera, spp);
    return how(scene, camera, settings);
}

// The guide a render of `scene` through `camera` at `spp` traces
// (render/renderer.h: its rays from the camera's samples), traced once per
// ray count and majorant: the renders of a session differ in k_s and
// contrast, which the guide does not see (it attenuates by the majorant).
std::shared_ptr<const LightGuide> FitSession::light_guide(const Scene& scene, const PinholeCamera& camera,
                                                          int spp) const {
    IntegratorSettings integrator = settings_.integrator;
    integrator.light_guide_photons = light_guide_photons(double(camera.width()) * camera.height() * spp);
    const Spectrum majorant = scene.medium->majorant();
    const std::lock_guard<std::mutex> lock(guides_mutex_);
    for (const TracedGuide& g : guides_)
        if (g.photons == integrator.light_guide_photons && g.majorant == majorant) return g.guide;
    std::shared_ptr<const LightGuide> guide = light_guide_for(scene, integrator, settings_.seed);
    // A few at most: a session meets two ray counts (the fitting and the
    // final size) and a majorant per density scale.
    constexpr std::size_t kMostGuides = 8;
    if (guides_.size() == kMostGuides) guides_.erase(guides_.begin());
    guides_.push_back({integrator.light_guide_photons, majorant, guide});
    return guide;
}

RenderResult FitSession::render_at(const std::array<double, 3>& ks, const std::array<double, 3>& contrast,
                                   int spp) const {
    return with_medium(camera_, ks, contrast, spp,
                       [&](const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings) {
                           return render(scene, camera, settings);
                       });
}

// A render at ks and contrast through `camera` with `spp` samples per pixel,
// in independent halves and quarters, for S_material's noise estimate.
SplitFilms FitSession::split_render(const PinholeCamera& camera, const std::array<double, 3>& ks,
                                    const std::array<double, 3>& contrast, int spp) {
    SplitFilms films = with_medium(camera, ks, contrast, spp,
                                   [&](const Scene& scene, const PinholeCamera& at, const RenderSettings& settings) {
                                       return render_quarters(scene, at, settings);
                                   });
    if (progress_) progress_->advance();
    return films;
}

// One fitting render at ks; the first chooses the sample count: doubled from
// kFirstFitSpp until A's standard error is below options.noise in every
// channel (measured at the photo's mean luminance) and the estimated per-pixel
// error below options.error. The light's rare paths make both estimates read
// low at a few samples, hence no lower start.
RenderResult FitSession::fitting_render(const std::array<double, 3>& ks, const std::array<double, 3>& contrast) {
    RenderResult r;
    if (outcome_.spp > 0) {
        r = render_at(ks, contrast, outcome_.spp);
    } else {
        for (int spp = std::min(kFirstFitSpp, options_.spp_max);; spp *= 2) {
            r = render_at(ks, contrast, spp);
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

// A row of fit.csv for a render at ks and contrast.
FitRecord& FitSession::record(const std::array<double, 3>& ks, const std::array<double, 3>& contrast,
                              const Film& film) {
    const DisplayStatistics st = display_statistics(film, outcome_.exposure, LumaHalves::Measure);
    const Appearance look = compare_appearance(photo_histogram_, photo_spectrum_, st, pixels_per_side_);
    FitRecord rec;
    rec.iteration = int(outcome_.records.size());
    rec.seconds = clock_.seconds();
    rec.spp = film.spp();
    rec.ks = ks;
    rec.contrast = contrast;
    rec.density_scale = density_scale_;
    rec.sharpen = volume_.noise.sharpen;
    for (int c = 0; c < 3; ++c) {
        rec.a_photo[c] = photo_histogram_.mean(c);
        rec.a_render[c] = st.a[c];
        rec.a_sigma[c] = st.a_sigma[c];
        rec.delta[c] = st.a[c] - photo_histogram_.mean(c);
        rec.distance[c] = look.d[c];
        rec.s_photo[c] = look.s_photo[c];
        rec.s_render[c] = look.s_render[c];
        rec.at_black[c] = st.histogram.proportion(c, 0);
        rec.at_white[c] = st.histogram.proportion(c, 255);
    }
    rec.structure = look.structure;
    rec.structure_error = look.structure_error;
    rec.orientation_photo = look.photo.orientation;
    rec.orientation_render = look.render.orientation;
    rec.strength_photo = look.photo.strength;
    rec.strength_render = look.render.strength;
    outcome_.records.push_back(rec);
    return outcome_.records.back();
}

// Renders at both bounds: they bracket every reachable channel, and they fix
// the exposure (when not given) in the middle of the range where every
// channel can reach the photo.
void FitSession::bracket(FitDriver& driver) {
    const std::array<double, 3> k_lo = limits_.k_min;
    const std::array<double, 3> k_hi{limits_.k_max, limits_.k_max, limits_.k_max};
    const std::array<double, 3>& g = outcome_.contrast_start;
    const RenderResult r_lo = fitting_render(k_lo, g);
    const RenderResult r_hi = fitting_render(k_hi, g);
    if (options_.exposure == 0.f)
        outcome_.exposure = float(exposure_in_reach(
            r_lo.film, r_hi.film, {photo_histogram_.mean(0), photo_histogram_.mean(1), photo_histogram_.mean(2)}));
    // Copies: the second row may move the first.
    const FitRecord at_lo = record(k_lo, g, r_lo.film);
    const FitRecord at_hi = record(k_hi, g, r_hi.film);
    if (bisects(options_.method)) driver.observe_bounds(at_lo.delta, at_hi.delta, clipped(at_lo), clipped(at_hi));
}

FitOutcome FitSession::run(Progress* progress) {
    progress_ = progress;
    clock_ = Stopwatch();
    outcome_ = FitOutcome{};
    outcome_.limits = limits_;
    outcome_.spp = options_.spp;
    outcome_.width = camera_.width();
    outcome_.height = camera_.height();
    const std::optional<FitStart>& from = options_.start;
    outcome_.ks_start = from ? from->ks : options_.ks_start.value_or(optics_.ks);
    outcome_.contrast_start = from ? from->contrast : options_.contrast_start.value_or(optics_.contrast);
    outcome_.density_scale_start = optics_.density_scale;
    outcome_.density_scale_max =
        from ? std::max(from->density_scale_max, optics_.density_scale) : kMaxDensityGain * optics_.density_scale;
    set_density_scale(optics_.density_scale);
    outcome_.exposure = from ? from->exposure : options_.exposure;
    outcome_.exposure_matched = from ? from->exposure_matched : options_.exposure == 0.f;
    if (from) {
        // The error the first contrast step chooses its blocks by where the
        // steps render at the fitting size (choose_spread_block).
        outcome_.estimated_error = from->estimated_error;
        for (int c = 0; c < 3; ++c) outcome_.ks[c] = std::clamp(from->ks[c], limits_.k_min[c], limits_.k_max);
        outcome_.contrast = from->contrast;
        fit_contrast(from->brightness_slope);
    } else {
        fit_from_bounds();
    }
    if (options_.method != FitMethod::None) mark_clipped_channels();
    outcome_.renders = fitting_renders();
    outcome_.seconds = clock_.seconds();
    progress_ = nullptr;
    return outcome_;
}

// The fit from the volume's own start: renders at both k_s bounds where
// they bracket the search or fix the exposure, the k_s search, then (--fit
// contrast) the contrast steps.
void FitSession::fit_from_bounds() {
    const bool fitting = options_.method != FitMethod::None;
    const std::array<double, 3>& g = outcome_.contrast_start;
    FitDriver driver(options_.method, outcome_.ks_start, k_search_limits());
    if (bisects(options_.method) || (fitting && options_.exposure == 0.f)) bracket(driver);
    // --fit contrast keeps renders for at least two of its steps.
    const int k_renders = options_.max_renders - (options_.method == FitMethod::Contrast ? 2 * step_cost() : 0);
    while (fitting && !driver.done() && fitting_renders() < k_renders) {
        const std::array<double, 3> ks = driver.k();
        const RenderResult r = fitting_render(ks, g);
        if (outcome_.exposure == 0.f) outcome_.exposure = matching_exposure(r.film, photo_);
        const FitRecord& rec = record(ks, g, r.film);
        driver.observe(rec.delta, clipped(rec));
    }
    if (!fitting && outcome_.exposure == 0.f) {
        // Nothing fitted: still match the exposure, from one fitting render.
        const RenderResult r = render_at(outcome_.ks_start, g, outcome_.spp > 0 ? outcome_.spp : 64);
        outcome_.exposure = matching_exposure(r.film, photo_);
    }
    finish(driver);
    if (options_.method == FitMethod::Contrast) fit_contrast(brightness_slopes());
}

void FitSession::finish(const FitDriver& driver) {
    const bool fitting = options_.method != FitMethod::None;
    outcome_.converged = true;
    outcome_.contrast = outcome_.contrast_start;
    outcome_.density_scale = density_scale_;
    for (int c = 0; c < 3; ++c) {
        outcome_.ks[c] = fitting ? driver.best_k()[c] : outcome_.ks_start[c];
        outcome_.state[c] = driver.state(c);
        if (driver.state(c) == ChannelState::Unreachable) outcome_.reason[c] = driver.reason(c);
        if (driver.state(c) == ChannelState::Searching)
            outcome_.reason[c] = std::string(channel_name(c)) + ": not converged within --fit-max-renders " +
                                 std::to_string(options_.max_renders) + " renders";
        if (driver.state(c) != ChannelState::Converged) outcome_.converged = false;
    }
    // About the k_s just chosen (the brightness check's first step).
    if (fitting && outcome_.records.size() >= 2) outcome_.brightness_slope = brightness_slopes();
}

// A photo channel with most object pixels at level 0 or 255 says only
// "this dark or darker" / "this bright or brighter": a render whose A matches
// it is not thereby the stone, so the channel is reported as clipped, not
// converged (a pure black or white photo "converged" before). The same holds
// for the render at the fitted k_s and contrast where the exposure was given
// (--exposure far too high or low): its A is only a bound too. Where the
// exposure was matched to the photo, a render that clips is what the photo
// asks for: a near-white stone (Marble021, A 243) on a lit object whose
// shading spreads its levels by 20 has half its pixels at 255 at the
// photo's mean, at any exposure. A there is still a mean that grows with
// k_s and matches, so the channel keeps its state and the clipping is
// reported as a warning.
void FitSession::mark_clipped_channels() {
    const std::vector<Rgb8> levels = photo_.foreground_levels();
    if (levels.empty()) return;
    for (int c = 0; c < 3; ++c) {
        std::size_t low = 0, high = 0;
        for (const Rgb8& l : levels) {
            low += l[c] == 0;
            high += l[c] == 255;
        }
        const double share = double(std::max(low, high)) / double(levels.size());
        const FitRecord* r = final_record(c);
        const double render_share = r ? std::max(r->at_black[c], r->at_white[c]) : 0.0;
        const bool render_white = r && r->at_white[c] >= r->at_black[c];
        char why[400];
        if (share > kClippedShare) {
            std::snprintf(why, sizeof why,
                          "%s: %.0f%% of the photo's object pixels are at level %d (clipped), so its brightness "
                          "there is only a bound and the fit cannot be judged; use a photo exposed %s",
                          channel_name(c), 100.0 * share, high >= low ? 255 : 0, high >= low ? "darker" : "brighter");
        } else if (render_share > kClippedShare && outcome_.exposure_matched) {
            std::snprintf(why, sizeof why,
                          "%s: %.0f%% of the render's object pixels are at level %d: the photo's mean level %.0f "
                          "leaves the object's shading no room, so the material shows only where the render is not "
                          "clipped (a %s --exposure shows more of it and matches the photo's mean less)",
                          channel_name(c), 100.0 * render_share, render_white ? 255 : 0, photo_histogram_.mean(c),
                          render_white ? "lower" : "higher");
            outcome_.warnings.push_back(why);
            continue;
        } else if (render_share > kClippedShare) {
            std::snprintf(why, sizeof why,
                          "%s: %.0f%% of the render's object pixels are at level %d at exposure %.4g (the render "
                          "clips), so its brightness is only a bound and the fit cannot be judged; use a %s --exposure "
                          "(0: found from the renders)",
                          channel_name(c), 100.0 * render_share, render_white ? 255 : 0, outcome_.exposure,
                          render_white ? "lower" : "higher");
        } else {
            continue;
        }
        outcome_.state[c] = ChannelState::Clipped;
        outcome_.reason[c] = why;
        outcome_.converged = false;
    }
}

// The latest fitting render (not a shading render) at the fitted k_s,
// contrast and density scale of channel c, or none.
const FitRecord* FitSession::final_record(int c) const {
    for (auto it = outcome_.records.rbegin(); it != outcome_.records.rend(); ++it)
        if (!it->shading && it->ks[c] == outcome_.ks[c] && it->contrast[c] == outcome_.contrast[c] &&
            it->density_scale == outcome_.density_scale)
            return &*it;
    return nullptr;
}

// The renders at the final size take as many samples per image as a
// fitting render (16 per pixel where that has 256 at a quarter of the
// width), so each costs about as much. The noise this leaves (on Onyx010
// 13–21 levels against S of 27–36) is taken out by the halves' covariance
// (material_spread) and widens only S's own scatter. Where a faint stone's
// spread hides in that noise (choose_spread_block), the fit takes more
// (raise_spread_spp), or --fit-spread-spp sets their count.
int FitSession::spread_spp() const {
    if (options_.spread_spp > 0) return options_.spread_spp;
    if (spread_spp_raised_ > 0) return spread_spp_raised_;
    if (!spread_at_final_size_) return outcome_.spp;
    const double pixel_ratio = double(camera_.width()) * camera_.height() /
                               (double(spread_camera().width()) * spread_camera().height());
    return std::max(kMinSpreadSpp, int(std::lround(outcome_.spp * pixel_ratio)));
}

int FitSession::fitting_renders() const {
    const auto rendered = std::count_if(outcome_.records.begin(), outcome_.records.end(),
                                        [](const FitRecord& r) { return !r.from_final_size; });
    return int(rendered) + spread_renders_;
}

namespace {
// The most fitting renders the brightness check takes to move k_s.
constexpr int kMaxBrightnessRenders = 3;
// The check moves a channel whose ΔA at full size it foresees at this share
// of the tolerance or more: the foresight itself errs by up to 0.5 levels
// (docs/design.md, "The fit"), so a channel left just inside the tolerance
// could end the final render outside it.
constexpr double kBrightnessAim = 0.4;
// The most of a channel's object pixels at level 255 (in the fitting render
// at the fitted k_s) for which A at the final size is taken from the fit's
// renders there. At their 16 samples a pixel, a rare bright sample in a
// pixel near white loses its energy at the clip, a bias that does not fall
// as 1/samples, and the extrapolation from their halves read low: on
// Marble021 (56 % of the pixels at 255) by 1.6–1.9 levels
// (tests/fit/test_fitter.cpp shows the mechanism). Above it both sizes are
// rendered with as many samples per pixel, which lose alike at the clip.
// Highlights far above white lose nothing (the round-trip test's 6.5 %).
constexpr double kForesightWhiteShare = 0.1;
// The most of a channel's object pixels whose clip at white the noise of
// those renders decides (noise_clipped_share: one half at 255, the other
// below) for which the same holds. The share at 255 misses a stone just
// below white: on Marble01 in the vase 2–10 % of the fitting render's pixels
// were at 255, but in 23–30 % of the final size's the halves disagreed, and
// the final render ended 0.9 and 1.2 levels above the photo in red and
// green, foreseen at −0.2 and +0.4. The demo photo's red (its highlights)
// read 0.04–0.11 in the vase and the bunny, where the fit's foresight keeps
// the final render within the tolerance, Onyx010's channels 0.03 at most
// (docs/design.md, "The fit").
constexpr double kForesightNoiseClippedShare = 0.15;
}  // namespace

// Per channel, the record final_brightness starts from and whether its k_s
// was fitted (a brightness slope is known).
struct FitSession::BrightnessStart {
    std::array<const FitRecord*, 3> at{};
    std::array<bool, 3> fitted{};
};

FitSession::BrightnessStart FitSession::brightness_start() const {
    BrightnessStart b;
    for (int c = 0; c < 3; ++c) {
        b.at[c] = final_record(c);
        b.fitted[c] = b.at[c] && outcome_.brightness_slope[c] > 0.0;
    }
    return b;
}

bool FitSession::brightness_from_fit() const {
    if (!spread_at_final_size_) return false;
    const BrightnessStart b = brightness_start();
    for (int c = 0; c < 3; ++c)
        if (b.fitted[c] && !(b.at[c]->a_final_size[c] >= 0.0 && b.at[c]->at_white[c] <= kForesightWhiteShare &&
                             b.at[c]->noise_clipped[c] <= kForesightNoiseClippedShare))
            return false;
    return true;
}

FitSession::FinalBrightness FitSession::final_brightness(int spp, const Film* full_size) const {
    FinalBrightness f;
    f.ks = outcome_.ks;
    const auto look = [&](const PinholeCamera& camera, const std::array<double, 3>& ks, int samples) {
        const Film film = with_medium(camera, ks, outcome_.contrast, samples,
                                      [&](const Scene& scene, const PinholeCamera& at, const RenderSettings& settings) {
                                          return render(scene, at, settings).film;
                                      });
        return display_statistics(film, outcome_.exposure);
    };
    const BrightnessStart start = brightness_start();
    const std::array<const FitRecord*, 3>& at = start.at;
    const std::array<bool, 3>& fitted = start.fitted;
    f.from_fit = brightness_from_fit();
    for (int c = 0; c < 3; ++c)
        if (at[c]) {
            f.white_share[c] = at[c]->at_white[c];
            f.noise_clipped[c] = at[c]->noise_clipped[c];
        }
    if (f.from_fit) {
        f.spp = spread_spp();
        for (int c = 0; c < 3; ++c)
            if (fitted[c]) f.size_change[c] = at[c]->a_final_size[c] - at[c]->a_render[c];
    } else {
        if (full_size && (full_size->fewest_samples() != spp || full_size->width() != final_camera_.width() ||
                          full_size->height() != final_camera_.height()))
            throw Error("internal: the full-size render for the brightness check has other than its samples or size");
        f.spp = spp;
        f.from_final_render = full_size != nullptr;
        const DisplayStatistics at_full = full_size ? display_statistics(*full_size, outcome_.exposure)
                                                    : look(final_camera_, f.ks, spp),
                                at_fit = look(camera_, f.ks, spp);
        if (at_full.pixels == 0 || at_fit.pixels == 0) return f;
        for (int c = 0; c < 3; ++c) f.size_change[c] = at_full.a[c] - at_fit.a[c];
    }
    for (int c = 0; c < 3; ++c) f.delta[c] = fitted[c] ? at[c]->delta[c] + f.size_change[c] : 0.0;
    f.expected = f.delta;
    // ΔA expected at full size at k: where the fit rendered at full size, a
    // render there like its steps' (same samples per image, same random
    // numbers, A extrapolated from its halves); else at the fitting size,
    // less the change of A with size.
    const auto foresee = [&](const std::array<double, 3>& k) {
        std::array<double, 3> a{};
        if (f.from_fit) {
            a = extrapolated_brightness(
                with_medium(final_camera_, k, outcome_.contrast, spread_spp(),
                            [&](const Scene& scene, const PinholeCamera& at, const RenderSettings& settings) {
                                return render_quarters(scene, at, settings);
                            }),
                outcome_.exposure);
        } else {
            a = look(camera_, k, outcome_.spp).a;
            for (int c = 0; c < 3; ++c) a[c] += f.size_change[c];
        }
        for (int c = 0; c < 3; ++c) a[c] -= photo_histogram_.mean(c);
        return a;
    };
    // Secant steps from the fit's slope (a bisection's slope is a secant
    // over the whole bracket, and A is curved in k_s: the local one is
    // found here).
    std::array<double, 3> slope = outcome_.brightness_slope;
    for (int step = 0; step < kMaxBrightnessRenders; ++step) {
        std::array<double, 3> k = f.ks;
        bool moved = false;
        for (int c = 0; c < 3; ++c)
            if (fitted[c] && std::abs(f.expected[c]) >= kBrightnessAim * limits_.tolerance) {
                k[c] = std::clamp(f.ks[c] - f.expected[c] / slope[c], k_min_at(c, outcome_.contrast[c]),
                                  limits_.k_max);
                moved = moved || k[c] != f.ks[c];
            }
        if (!moved) break;
        const std::array<double, 3> expected = foresee(k);
        for (int c = 0; c < 3; ++c) {
            if (k[c] == f.ks[c]) continue;
            const double secant = (expected[c] - f.expected[c]) / (k[c] - f.ks[c]);
            if (secant > 0.0) slope[c] = secant;
            // A step that lands further from the photo is learned from, not
            // kept: where most pixels clip, A is flat in k_s, and a step by
            // the slope there overshot (a near-white photo on the cow: from
            // +4.8 levels to −91).
            if (std::abs(expected[c]) >= std::abs(f.expected[c])) continue;
            f.ks[c] = k[c];
            f.expected[c] = expected[c];
        }
        ++f.renders;
    }
    return f;
}

namespace {
// --fit contrast's first step moves A by 8–12 levels (the contrast rises
// up to 4×, and A with it; Onyx010), and its Newton steps match A in k_s and
// g together from there: bisecting k_s to 1 level beforehand costs renders
// whose precision that step throws away, so the search hands over at this
// |ΔA| (from 3 to 5 it saved one render on the demo and on Onyx010, and
// both still end within 1 level).
constexpr double kContrastHandover = 5.0;
}  // namespace

FitLimits FitSession::k_search_limits() const {
    FitLimits limits = limits_;
    if (options_.method == FitMethod::Contrast) limits.tolerance = kContrastHandover;
    return limits;
}

double FitSession::k_min_at(int c, double contrast) const {
    return k_min_for(optics_, lowest_level_[c], c, contrast);
}

// dA/dk_s per channel at the fitted k_s, from the k_s-only renders: the
// slope at k of the parabola through the render there and the nearest
// renders below and above it (a centred difference where they are equally
// far, as halving the bracket leaves them). The false position's bracket
// often keeps one far end (the demo's red: k_s 1.13 between 1.72 and
// k_min −0.48), and the secant between the ends, which this was, read
// 44 levels a unit where A rises about 27 (the parabola: 31), so that the
// contrast steps moved k_s little more than half as far as A needed. Where
// a side has no render: the secant through the nearest render, else the
// bounds'.
std::array<double, 3> FitSession::brightness_slopes() const {
    std::array<double, 3> slope{};
    const auto& recs = outcome_.records;
    for (int c = 0; c < 3; ++c) {
        const double k = outcome_.ks[c];
        const FitRecord* at = nullptr;
        const FitRecord* below = nullptr;
        const FitRecord* above = nullptr;
        for (const FitRecord& r : recs) {
            if (std::abs(r.ks[c] - k) <= 1e-6 && !at) at = &r;
            if (r.ks[c] < k - 1e-6 && (!below || r.ks[c] > below->ks[c])) below = &r;
            if (r.ks[c] > k + 1e-6 && (!above || r.ks[c] < above->ks[c])) above = &r;
        }
        if (at && below && above) {
            const double h_lo = k - below->ks[c], h_hi = above->ks[c] - k;
            slope[c] = (h_lo * h_lo * (above->a_render[c] - at->a_render[c]) +
                        h_hi * h_hi * (at->a_render[c] - below->a_render[c])) /
                       (h_lo * h_hi * (h_lo + h_hi));
        } else if (at && (below || above)) {
            const FitRecord* other = below ? below : above;
            slope[c] = (other->a_render[c] - at->a_render[c]) / (other->ks[c] - k);
        } else if (below && above) {
            slope[c] = (above->a_render[c] - below->a_render[c]) / (above->ks[c] - below->ks[c]);
        }
        if (!(slope[c] > 0.0) && recs.size() >= 2 && recs[1].ks[c] > recs[0].ks[c])
            slope[c] = (recs[1].a_render[c] - recs[0].a_render[c]) / (recs[1].ks[c] - recs[0].ks[c]);
        if (!(slope[c] > 0.0)) slope[c] = 1.0;  // A does not grow with k_s here: step one k_s per level
    }
    return slope;
}

namespace {

// The more contrast, the more voxels are clipped to level 0 or 1, and the
// less the volume has the photo's histogram of levels (the demo's volume:
// 12–18 % of the voxels at 4, a third to a half at 8, more than half at 16,
// where S hardly grows any more): where the photo's S needs more, --fit
// contrast raises the density scale instead.
constexpr double kContrastCeiling = 4.0;
// At a fixed contrast S_material grows about as the density scale to a
// power α: the factor by which a step in density scale is expected to raise
// S, so that the contrasts can be lowered to match. It differs between
// channels and falls as the density grows (the demo's vase: 0.6–0.9 from
// 20 to 60 at contrast 1; blue at the ceiling, where the density rises,
// 0.47 from 20 to 61 and 0.36 from 61 to 113; Onyx010's 0.2–0.3 from 20
// to 61), so the first step takes one from the ceiling's range and later
// steps the one measured by the steps before (bounded). Too large an α
// raises the density by too little, and each further step costs three
// renders (0.5: Onyx010 raised it three times, in 22 renders; 0.35:
// twice, in 19); too small a one overshoots a scale that never falls back.
constexpr double kDensityExponent = 0.35;
constexpr double kDensityExponentMin = 0.3, kDensityExponentMax = 1.5;
// The most the fit raises the density scale per step (in all:
// FitOutcome::density_scale_max).
constexpr double kMaxDensityStep = 4.0;
// A smaller step is not worth forgetting the search for.
constexpr double kMinDensityStep = 1.1;
// The least d ln S / d ln g the contrast steps start from (spread_elasticity):
// a bound on a slope that would otherwise be nearly 0, not a measured one.
constexpr double kMinSpreadElasticity = 0.1;

}  // namespace

// A change of ΔS smaller than this (gray levels) says too little beside
// the renders' noise (a reading of S scatters by about half a level from one
// render seed to the next, and a change is the difference of two) to
// correct the Jacobian by; nor of ΔA, unless the two
// renders' own standard errors of A say a smaller change is plain:
// kJacobianNoiseMultiple of the change's standard error, at least
// kJacobianMinChangeA. A at 128 spp has a standard error of 0.04–0.08
// levels; at the 2-level rule a step whose A missed the Jacobian's
// prediction by 1.9 levels taught nothing, and a wrong dA/dg learnt on a
// long step stayed (docs/design.md, "Contrast").
constexpr double kJacobianMinChange = 2.0;
constexpr double kJacobianNoiseMultiple = 4.0;
constexpr double kJacobianMinChangeA = 0.5;

// The state of --fit contrast's search, per channel.
struct FitSession::ContrastSearch {
    std::array<double, 3> k{}, g{};
    // The Jacobian of (ΔA, ΔS) in (k_s, g) per channel: dA/dk_s from the
    // k_s search, dS/dg from the first step (S grows about in proportion to
    // g: the levels' spread about their mean does exactly), the cross terms
    // 0 until the steps show them; every step corrects it (Broyden).
    std::array<BroydenJacobian2, 3> jacobian{};
    std::array<bool, 3> done{};
    std::array<double, 3> best_score{1e300, 1e300, 1e300};
    // The step before this one at this density scale, for the Jacobian's
    // update (a step in density scale moves A and S as well).
    std::array<double, 3> k_prev{}, g_prev{};
    std::array<std::array<double, 2>, 3> residual_prev{};
    std::array<double, 3> a_sigma_prev{};  // that step's standard error of A
    bool have_prev = false;
    // The last render's contrast, S and ΔA per channel, and the same at the
    // last step in density scale (density_at_raise > 0 once there was one):
    // a channel at the same contrast and near the photo's A in both
    // measures α.
    std::array<double, 3> g_last{}, s_last{}, delta_last{}, g_at_raise{}, s_at_raise{}, delta_at_raise{};
    double density_at_raise = 0.0;
    // Whether the last step in density scale was held at kMaxDensityStep,
    // short of the factor the stone's spread asked for.
    bool rise_capped = false;
    double alpha = kDensityExponent;
    // S_material's block (0 until the first step chose it), the photo's S
    // there, and per channel whether the steps' noise lets S be read at all.
    int block = 0;
    std::array<double, 3> s_photo{};
    std::array<bool, 3> spread_seen{true, true, true};
    // The warnings for the channels whose S the first step could not read,
    // given once the count of samples is settled (raise_spread_spp).
    std::vector<std::string> hidden_warnings;
    // Stopped for the sharper stone (FitOptions::stop_at_density_ceiling,
    // stop_at_first_rise), and whether at the first rise.
    bool stopped = false;
    bool stopped_at_first_rise = false;
};

// One step of --fit contrast at (k_s, g): the volume and its mean medium
// (contrast 0: the shading) in two halves each through the spread camera,
// for S_material, and the volume at the fitting size, for fit.csv's row (the
// merged halves where the spread camera is the fitting renders' own; its
// shading render is then a row too). A, D and the structure at the final
// size would not compare with the fitting renders' rows, so the row is taken
// at the fitting size: from the final-size volume render box-downsampled to
// it where the sizes allow (box_factor_: the same samples in the fitting
// camera's pixels, no render of its own), else from a fitting render. A
// fitting render at the same k_s, contrast and density scale as one made
// before (the first step's, at the k_s search's result) would be the same
// image: that render's record serves instead.
struct FitSession::StepRenders {
    SplitFilms shading, render;
    std::optional<Film> whole;  // none where an earlier record serves
    bool downsampled = false;   // whole is render's, box-downsampled
};

FitRecord* FitSession::rendered_at(const std::array<double, 3>& ks, const std::array<double, 3>& contrast) {
    for (FitRecord& r : outcome_.records)
        if (!r.shading && r.ks == ks && r.contrast == contrast && r.density_scale == density_scale_) return &r;
    return nullptr;
}

FitSession::StepRenders FitSession::step_renders(const std::array<double, 3>& ks,
                                                 const std::array<double, 3>& contrast) {
    StepRenders r{split_render(spread_camera(), ks, {0.0, 0.0, 0.0}, spread_spp()),
                  split_render(spread_camera(), ks, contrast, spread_spp()), {}};
    if (spread_at_final_size_) {
        spread_renders_ += 2;
        if (rendered_at(ks, contrast)) return r;
        r.downsampled = box_factor_ > 0;
        r.whole = r.downsampled ? box_downsampled(r.render.merged(), box_factor_) : fitting_render(ks, contrast).film;
    } else {
        r.whole = r.render.merged();
        record(ks, {0.0, 0.0, 0.0}, r.shading.merged()).shading = true;
    }
    return r;
}

// --fit contrast, after k_s matched A: k_s and the contrast g_c together
// until A and S_material match in every channel (docs/design.md,
// "Contrast"). Each step renders the mean medium (contrast 0: the shading)
// and the volume at (k_s, g), both at the fitting renders' random numbers
// (step_renders). Per channel, Newton's step for (ΔA, ΔS) = 0 in (k_s, g)
// with a Jacobian that every step corrects (contrast_step): both levers
// move both A and S (raising g from 1 to 2 raised A by 11–19 levels in
// the round-trip test), and one-dimensional rules, each blind to the other
// lever, took that for their own lever's effect. ΔA is judged at the final
// size where the steps render there, S_material against the photo's S at
// the same scale. The channels are independent (one render serves all
// three); a channel stops when both |ΔA| < 1 and |ΔS| < s_tolerance, and
// keeps the best (k_s, g) it saw. Where a channel
// would need a contrast above kContrastCeiling, the density scale (shared
// by the channels) rises instead (raise_density_scale).
void FitSession::fit_contrast(const std::array<double, 3>& brightness_slope) {
    ContrastSearch st;
    st.k = outcome_.ks;
    st.g = outcome_.contrast_start;
    for (int c = 0; c < 3; ++c) st.jacobian[c].m[0][0] = brightness_slope[c];
    while (fitting_renders() + step_cost() <= options_.max_renders) {
        const StepRenders step = step_renders(st.k, st.g);
        const bool first = st.block == 0;
        const MaterialSpread spread = first ? choose_spread_block(st, step)
                                            : material_spread(step.render, step.shading, outcome_.exposure, st.block);
        FitRecord& rec = step.whole ? record(st.k, st.g, *step.whole) : *rendered_at(st.k, st.g);
        if (step.whole) rec.from_final_size = step.downsampled;
        rec.s_material = spread.s;
        rec.s_material_noise = spread.noise;
        rec.s_photo_scaled = st.s_photo;
        // The row stays (a render like any); the step is made again at more
        // samples and rewrites its readings.
        if (first && raise_spread_spp(st)) continue;
        if (first) {
            for (const std::string& w : st.hidden_warnings) outcome_.warnings.push_back(w);
        }
        // ΔA where the final render will have it: at the final size, from
        // its halves there (the fitting size's A differs by up to 10 levels
        // on a small object; docs/design.md, "Contrast").
        std::array<double, 3> delta = rec.delta;
        if (spread_at_final_size_) {
            rec.a_final_size = extrapolated_brightness(step.render, outcome_.exposure);
            rec.noise_clipped = noise_clipped_share(step.render, outcome_.exposure);
            for (int c = 0; c < 3; ++c) delta[c] = rec.a_final_size[c] - photo_histogram_.mean(c);
        }
        bool all_done = true;
        st.g_last = st.g;
        st.s_last = spread.s;
        st.delta_last = delta;
        for (int c = 0; c < 3; ++c) {
            contrast_step(st, c, delta[c], spread.s[c], rec.a_sigma[c]);
            all_done = all_done && st.done[c];
        }
        st.have_prev = true;
        if (all_done) break;
        // A step in density scale needs two more steps to be judged; it
        // changes every channel's S, so not where one channel's S is hidden.
        const bool every_spread_seen = st.spread_seen == std::array<bool, 3>{true, true, true};
        const bool first_rise = !(st.density_at_raise > 0.0);
        const bool raised = every_spread_seen && options_.fit_density &&
                            fitting_renders() + 2 * step_cost() <= options_.max_renders &&
                            raise_density_scale(st, st.s_photo);
        if (!raised) continue;
        if (options_.stop_at_density_ceiling && at_density_ceiling(density_scale_, outcome_.density_scale_max)) {
            st.stopped = true;
            break;
        }
        if (options_.stop_at_first_rise && first_rise && !st.rise_capped) {
            st.stopped = st.stopped_at_first_rise = true;
            break;
        }
    }
    finish_contrast(st);
}

// The block S_material is read over, from the first step: the one the
// final render's noise will allow (material_block of its expected error:
// this render's at the final sample count), or larger, where the steps' own
// noise is more than kSpreadNoiseShare times the photo's spread over it
// (quiet_block). Where even kMaxMaterialBlock's blocks leave a channel's
// noise above that multiple of both the photo's spread and its own S, S's
// scatter from one step to the next is larger than either (Marble021, a
// near-white marble: at 8-px blocks noise 4.7 levels against the photo's
// 1.7 and S 0–0.7; S read 0 to 21 and the contrast ran to its cap), and a
// search on it follows the noise. Unless more samples would show it, within
// reach (raise_spread_spp: the step is then made again), that channel's
// contrast stays at its start and k_s alone matches A (contrast_step); the
// density scale stays too, and a warning says so. Returns the first step's
// spread.
MaterialSpread FitSession::choose_spread_block(ContrastSearch& st, const StepRenders& step) {
    const double error = spread_at_final_size_
                             ? step.render.merged().estimated_relative_error() *
                                   std::sqrt(double(spread_spp()) / double(std::max(1, settings_.spp)))
                             : outcome_.estimated_error;
    const QuietBlock q = quiet_block(photo_, step.render, step.shading, outcome_.exposure, spread_pixels_per_side_,
                                     material_block(error), kSpreadNoiseShare);
    st.block = q.block;
    st.s_photo = q.photo_spread;
    for (int c = 0; c < 3; ++c) {
        const SpreadReading r = read_spread(q.spread, q.photo_spread, c, options_.s_tolerance);
        st.spread_seen[c] = r.readable();
        outcome_.contrast_fitted[c] = st.spread_seen[c];
        if (st.spread_seen[c]) continue;
        // The scatter is of a square of levels: it falls as the noise
        // squared, and spp_for_noise takes its root. No count is named
        // where both spreads are under the S tolerance: more samples would
        // resolve a difference the fit does not need, and the photo has no
        // contrast at this scale to give the volume (a pattern finer than
        // the blocks: its search would flatten the stone).
        const bool both_small = std::max(q.photo_spread[c], q.spread.s[c]) < options_.s_tolerance;
        const int spp = both_small ? 0
                        : r.quiet  ? spp_for_noise(spread_spp(), std::sqrt(q.spread.scatter[c]),
                                                   std::sqrt(r.scatter_limit))
                                   : spp_for_noise(spread_spp(), q.spread.noise[c], r.noise_limit);
        outcome_.spread_spp_advised = std::max(outcome_.spread_spp_advised, spp);
        st.hidden_warnings.push_back(hidden_spread_warning(c, q, st.g[c], r, spp));
    }
    return q.spread;
}

// Where the first step found a channel's S_material hidden in its renders'
// noise and named a count that would show it (choose_spread_block), within
// kMaxSpreadSppGain times the count --fit-spread-spp 0 chose: that many
// times from now on, and the first step again there (the search has not
// moved yet). Not the count named: it is the least at which the noise
// falls under the rule's limit, where S still scatters as far as the rule
// allows. On Marble021's vase at the 32 named, red read 1.1 levels against
// the photo's 2.4 at contrast 1, within the S tolerance, and stayed there
// while green and blue rose to 2.3, tinting the dark voxels pink; at 64 all
// three came to 2.1–2.3. The first step's renders are spent and stay
// counted. A count the user gave is kept as given, and the count is raised
// once.
bool FitSession::raise_spread_spp(ContrastSearch& st) {
    const int advised = outcome_.spread_spp_advised;
    const int most = kMaxSpreadSppGain * spread_spp();
    if (options_.spread_spp > 0 || spread_spp_raised_ > 0 || advised <= 0 || advised > most ||
        fitting_renders() + 2 * step_cost() > options_.max_renders)
        return false;
    outcome_.spread_spp_raised_from = spread_spp();
    spread_spp_raised_ = most;
    outcome_.spread_spp_advised = 0;
    st.block = 0;
    st.spread_seen = {true, true, true};
    st.hidden_warnings.clear();
    return true;
}

// The warning for a channel whose S_material the fit's renders cannot show
// (choose_spread_block): too noisy over the largest block, or S² scattering
// too far between renders; with the --fit-spread-spp that would show it.
std::string FitSession::hidden_spread_warning(int c, const QuietBlock& q, double g, const SpreadReading& r,
                                             int spp) const {
    char why[520], advice[160] = "";
    if (r.quiet)
        std::snprintf(why, sizeof why,
                      "%s: the contrast was not fitted: over %d-px blocks S_material² scatters by %.2f levels² "
                      "from one of the fit's renders to the next at %d spp, more than %.2f (%g times the square of "
                      "the largest of the photo's spread there, %.1f, the render's, %.1f, and the S tolerance, "
                      "%.1f), so a search on it would follow the noise; the contrast stays at %.3g and k_s matches "
                      "A alone",
                      channel_name(c), q.block, q.spread.scatter[c], spread_spp(), r.scatter_limit,
                      kSpreadScatterShare, q.photo_spread[c], q.spread.s[c], options_.s_tolerance, g);
    else
        std::snprintf(why, sizeof why,
                      "%s: the contrast was not fitted: the fit's renders' noise over %d-px blocks (%.1f levels at "
                      "%d spp) is more than %.1f (%g times the largest of the photo's spread there, %.1f, the "
                      "render's, %.1f, and the S tolerance, %.1f), so S_material cannot be told from it; the "
                      "contrast stays at %.3g and k_s matches A alone",
                      channel_name(c), q.block, q.spread.noise[c], spread_spp(), r.noise_limit, kSpreadNoiseShare,
                      q.photo_spread[c], q.spread.s[c], options_.s_tolerance, g);
    if (spp > 0)
        std::snprintf(advice, sizeof advice,
                      " (--fit-spread-spp %d would show it; each contrast step renders two images at it)", spp);
    return std::string(why) + advice;
}

// The outcome of --fit contrast: the best (k_s, g) per channel (kept by
// contrast_step), the block and the photo's S there, each channel's state.
void FitSession::finish_contrast(const ContrastSearch& st) {
    outcome_.s_photo = st.s_photo;
    outcome_.material_block = st.block;
    outcome_.spread_spp = spread_spp();
    outcome_.density_scale = density_scale_;
    for (int c = 0; c < 3; ++c) outcome_.brightness_slope[c] = st.jacobian[c].m[0][0];
    if (st.stopped) {
        // Where the search goes on (start_from): the point it would render
        // next, at the new density scale.
        outcome_.stopped_at_density_ceiling = !st.stopped_at_first_rise;
        outcome_.stopped_at_first_rise = st.stopped_at_first_rise;
        outcome_.converged = false;
        outcome_.ks = st.k;
        outcome_.contrast = st.g;
        char why[240];
        if (st.stopped_at_first_rise)
            std::snprintf(why, sizeof why,
                          "stopped where the density scale's first rise (to %.4g) met the stone's need short of its "
                          "ceiling, for the sharper stone's fit to take the search on",
                          density_scale_);
        else
            std::snprintf(why, sizeof why,
                          "stopped where the density scale reached its ceiling (%.4g), for the sharper stone's fit to "
                          "take the search on",
                          density_scale_);
        for (int c = 0; c < 3; ++c) {
            outcome_.state[c] = ChannelState::Searching;
            outcome_.reason[c] = std::string(channel_name(c)) + ": " + why;
        }
        return;
    }
    outcome_.converged = true;
    for (int c = 0; c < 3; ++c) {
        outcome_.state[c] = st.done[c] ? ChannelState::Converged : ChannelState::Unreachable;
        outcome_.reason[c].clear();
        if (st.done[c]) continue;
        outcome_.converged = false;
        char why[320];
        if (st.spread_seen[c])
            std::snprintf(why, sizeof why,
                          "%s: A and S_material not both matched (|dA| < %.1f, |dS| < %.1f) within "
                          "--fit-max-renders %d; the best k_s and contrast are kept (S %.1f against the photo's %.1f)",
                          channel_name(c), limits_.tolerance, options_.s_tolerance, options_.max_renders,
                          outcome_.s_material[c], st.s_photo[c]);
        else
            std::snprintf(why, sizeof why, "%s: A not matched (|dA| < %.1f) within --fit-max-renders %d",
                          channel_name(c), limits_.tolerance, options_.max_renders);
        outcome_.reason[c] = why;
    }
}

// One channel's part of a step of --fit contrast, after a render that gave
// ΔA = delta and S_material = s: keep the best (k_s, g), stop when both
// match, else correct the Jacobian by the step just made (Broyden) and take
// the next k_s and g from it.
void FitSession::contrast_step(ContrastSearch& st, int c, double delta, double s, double a_sigma) {
    const double s_photo = st.s_photo[c];
    // Where the noise hides S (choose_spread_block), only A is judged and
    // the contrast stays.
    const double s_off = st.spread_seen[c] ? s - s_photo : 0.0;
    const double score = std::max(std::abs(delta) / limits_.tolerance, std::abs(s_off) / options_.s_tolerance);
    if (score < st.best_score[c]) {
        st.best_score[c] = score;
        outcome_.ks[c] = st.k[c];
        outcome_.contrast[c] = st.g[c];
        outcome_.s_material[c] = s;
    }
    if (score < 1.0) st.done[c] = true;
    if (st.done[c]) return;
    BroydenJacobian2& jac = st.jacobian[c];
    const std::array<double, 2> residual{delta, s_off};
    const double g = st.g[c];
    if (st.have_prev) {
        const double a_change_error = std::hypot(a_sigma, st.a_sigma_prev[c]);
        const double a_min = std::clamp(kJacobianNoiseMultiple * a_change_error, kJacobianMinChangeA, kJacobianMinChange);
        jac.update({st.k[c] - st.k_prev[c], g - st.g_prev[c]},
                   {residual[0] - st.residual_prev[c][0], residual[1] - st.residual_prev[c][1]},
                   {a_min, kJacobianMinChange});
    } else if (!(jac.m[1][1] > 0.0)) {
        jac.m[1][1] = first_spread_slope(s, g, spread_elasticity(c, g), s_photo);
    }
    st.k_prev[c] = st.k[c];
    st.g_prev[c] = g;
    st.residual_prev[c] = residual;
    st.a_sigma_prev[c] = a_sigma;
    // Newton's step for both; each step at most quadruples or quarters g,
    // and k_s then makes up for the contrast's actual move.
    double g_next = st.spread_seen[c] ? g + jac.newton_step(residual)[1] : g;
    if (g > 0.0) g_next = std::clamp(g_next, 0.25 * g, 4.0 * g);
    g_next = std::clamp(g_next, 0.0, kMaxContrast);
    const double k_next = st.k[c] - (delta + jac.m[0][1] * (g_next - g)) / jac.m[0][0];
    st.k[c] = std::clamp(k_next, k_min_at(c, g_next), limits_.k_max);
    st.g[c] = g_next;
}

// d ln S / d ln g at contrast g in channel c, as the volume's contrasted
// levels give it (contrasted_spread_elasticity): 1 while no voxel clips.
// Where most voxels clip it tends to 0, and a slope near 0 would send g to
// its cap or to a quarter on any reading's noise; kMinSpreadElasticity
// bounds it.
double FitSession::spread_elasticity(int c, double g) const {
    OpticalParams p = optics_;
    p.contrast[c] = g;
    return std::max(kMinSpreadElasticity, contrasted_spread_elasticity(level_histograms_, c, p));
}

// Where a channel's next contrast is above kContrastCeiling, the density
// scale rises instead (true where it did). The channel's S must still grow by the photo's S over
// the S its render had at the ceiling (S grows about in proportion to the
// contrast up to it); the density scale rises by the factor expected to
// give that (S ∝ density scale^α), for the channel that needs most. Every
// channel's contrast then starts from the proportional rule at the S the
// new density scale is expected to give, so the channel that needed most
// starts at the ceiling (above it where the step was capped at
// kMaxDensityStep; a channel that then matches there ends above it: the
// demo's blue at 5.2). The search starts again at the new density scale:
// no channel is done, the best (k_s, g) and the Jacobian's terms in g are
// forgotten (they belong to the old one); dA/dk_s is kept, and the next
// step does not correct it.
bool FitSession::raise_density_scale(ContrastSearch& st, const std::array<double, 3>& s_photo) {
    double need = 1.0;
    for (int c = 0; c < 3; ++c)
        if (!st.done[c] && st.g[c] > kContrastCeiling && st.s_last[c] > 0.0)
            need = std::max(need, s_photo[c] / st.s_last[c] * std::min(1.0, st.g_last[c] / kContrastCeiling));
    const double room = outcome_.density_scale_max / density_scale_;
    measure_density_exponent(st);
    const double wanted = std::pow(need, 1.0 / st.alpha);
    const double gain = std::min({wanted, kMaxDensityStep, room});
    if (!(gain >= kMinDensityStep)) return false;
    st.rise_capped = wanted > kMaxDensityStep;
    st.g_at_raise = st.g_last;
    st.s_at_raise = st.s_last;
    st.delta_at_raise = st.delta_last;
    st.density_at_raise = density_scale_;
    set_density_scale(density_scale_ * gain);
    const double s_gain = std::pow(gain, st.alpha);
    for (int c = 0; c < 3; ++c) {
        if (st.s_last[c] > 0.0)
            st.g[c] = std::clamp(st.g_last[c] * s_photo[c] / (st.s_last[c] * s_gain), 0.0, kMaxContrast);
        st.k[c] = std::clamp(st.k[c], k_min_at(c, st.g[c]), limits_.k_max);
        st.done[c] = false;
        st.best_score[c] = 1e300;
        BroydenJacobian2& jac = st.jacobian[c];
        jac.m[0][1] = jac.m[1][0] = jac.m[1][1] = 0.0;
    }
    st.have_prev = false;
    return true;
}

// α from the last step in density scale: the mean over the channels that
// were rendered at the same contrast at both density scales, each time
// within two tolerances of the photo's A (S changes with the brightness
// too: a render far from A says little about the density scale's share).
void FitSession::measure_density_exponent(ContrastSearch& st) const {
    if (!(st.density_at_raise > 0.0)) return;
    const double log_gain = std::log(density_scale_ / st.density_at_raise);
    const double near = 2.0 * limits_.tolerance;
    double sum = 0.0;
    int n = 0;
    for (int c = 0; c < 3; ++c)
        if (std::abs(st.g_last[c] - st.g_at_raise[c]) <= 0.01 * st.g_last[c] && st.s_last[c] > 0.0 &&
            st.s_at_raise[c] > 0.0 && std::abs(st.delta_last[c]) <= near && std::abs(st.delta_at_raise[c]) <= near)
            sum += std::log(st.s_last[c] / st.s_at_raise[c]) / log_gain, ++n;
    if (n > 0) st.alpha = std::clamp(sum / n, kDensityExponentMin, kDensityExponentMax);
}

FitStart start_from(const FitOutcome& fit) {
    FitStart start;
    start.ks = fit.ks;
    start.contrast = fit.contrast;
    for (int c = 0; c < 3; ++c)  // brightness_slopes' fallback where none was measured
        start.brightness_slope[c] = fit.brightness_slope[c] > 0.0 ? fit.brightness_slope[c] : 1.0;
    start.exposure = fit.exposure;
    start.exposure_matched = fit.exposure_matched;
    start.density_scale_max = fit.density_scale_max;
    start.spp = fit.spp;
    start.spread_spp = fit.spread_spp;
    start.estimated_error = fit.estimated_error;
    return start;
}

double first_spread_slope(double s, double g, double elasticity, double s_photo) {
    // S grows as the contrasted levels' spread does: in proportion to g
    // while no voxel clips (dS/dg = S/g), less as the contrast clips them
    // (the elasticity), except where S is the rounding of a flat material
    // (under kSpreadScatterFloor's level): a slope of 10⁻⁷ there sent g to a
    // quarter at every step on a one-colour photo, whose contrast moves
    // nothing. And at least the slope that brings the photo's S at the
    // contrast ceiling: a stone washed out by k_s (S a small share of the
    // photo's) spreads faster than in proportion as g rises and k_s falls
    // to hold A, and on a slope of S/g the first step's Broyden update,
    // weighing each lever by its own slope, put the whole of A's change on
    // k_s.
    const double proportional = s * s > kSpreadScatterFloor && g > 0.0 ? s / g * elasticity : std::max(s_photo, 1.0);
    return std::max(proportional, s_photo / kContrastCeiling);
}

bool at_density_ceiling(double density_scale, double density_scale_max) {
    return density_scale * kMinDensityStep > density_scale_max;
}

bool stopped_for_sharper_stone(const FitOutcome& fit) {
    return fit.stopped_at_density_ceiling || fit.stopped_at_first_rise;
}

SharpeningChoice sharpening_for(const FitOutcome& fit) {
    if (fit.stopped_at_density_ceiling) return {kDefaultSharpen, "the density scale rose to its ceiling"};
    if (fit.stopped_at_first_rise)
        return {kSharperStone, "the density scale's first rise met the stone's need, short of its ceiling"};
    if (!fit.converged) return {0.0, "the fit did not converge"};
    if (!(fit.density_scale > fit.density_scale_start))
        return {0.0, "the density scale stayed at the volume's own, where light spreads over many voxels"};
    if (at_density_ceiling(fit.density_scale, fit.density_scale_max))
        return {kDefaultSharpen, "the density scale rose to its ceiling"};
    return {kSharperStone, "the density scale rose, short of its ceiling"};
}

}  // namespace jade
