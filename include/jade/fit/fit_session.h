#pragma once
// The fit to the photo as one object (paper §5.4; docs/design.md, "The fit"
// and "Contrast"): fitting renders of the material volume at explicit k_s
// and contrast (the volume itself is never changed), the sample count they
// need, renders at both k_s bounds that bracket the search and fix the
// exposure, a driver that moves each channel's k_s until A matches, then
// (--fit contrast) a joint search of k_s and the contrast g_c until A and
// S_material match (S_material measured at the final render's size), and an
// outcome with each channel's state.
//
// Fitting renders leave the background out (only the object's pixels
// count), render a reduced image with the same random sequence every time,
// and share one majorant (that of k_s = k_max): every render makes the same
// tentative collisions, so A(k_s) changes smoothly with k_s.

#include "jade/core/progress.h"
#include "jade/core/timing.h"
#include "jade/fit/display.h"
#include "jade/fit/driver.h"
#include "jade/fit/appearance.h"
#include "jade/render/camera.h"
#include "jade/render/renderer.h"
#include "jade/render/scene.h"
#include "jade/volume/material_volume.h"
#include "jade/volume/photo.h"
#include "jade/volume/sharpen.h"

#include <array>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

namespace jade {

// The samples per pixel the first fitting render starts from when FitOptions::spp
// is 0 (FitSession::fitting_render). At a few samples the light's rare paths
// have not shown up and both of its estimates (A's standard error, the
// estimated error) read low; from 64 on the demo's error falls about as
// 1/√spp (README, "How the error falls"). 256 until the default command neared
// its 5 minutes (README, "The fit").
constexpr int kFirstFitSpp = 128;

// The fewest samples per pixel of a render S_material is read from, 8 in
// each half (render_quarters needs a turn of every replicate in each
// quarter).
constexpr int kMinSpreadSpp = 16;
// Where the first contrast step finds a channel's S_material hidden in its
// renders' noise and names a count that would show it within this many
// times its own, --fit-spread-spp 0 takes that many (16 → 64 at the default
// sizes; FitSession::raise_spread_spp says why not the count named): a
// near-white marble's contrast is then fitted without a second
// run, each step's two images at the final size costing half the final
// render (an eighth at 16). Beyond it a step would cost as much as the final
// render or more.
constexpr int kMaxSpreadSppGain = 4;

// What a fit takes from another's outcome on a volume alike, to start from
// (the sharper stone's fit, app/pipeline.h): its k_s, contrast, exposure,
// dA/dk_s, density scale's ceiling, sample counts and estimated error. The k_s search and
// the renders at both k_s bounds are skipped: the first contrast step
// judges A at the final size, where that fit matched it. The density scale
// starts from the volume's own, which the caller sets to that fit's.
struct FitStart {
    std::array<double, 3> ks{}, contrast{1, 1, 1};
    std::array<double, 3> brightness_slope{1, 1, 1};  // dA/dk_s (FitOutcome::brightness_slope)
    float exposure = 1.f;
    bool exposure_matched = false;   // to the photo (FitSession::mark_clipped_channels)
    double density_scale_max = 0.0;  // FitOutcome::density_scale_max
    int spp = 0, spread_spp = 0;     // of its fitting renders and of its S_material renders
    double estimated_error = 0.0;    // of its first fitting render (FitOutcome::estimated_error)
};

struct FitOptions {
    FitMethod method = FitMethod::Contrast;
    std::optional<std::array<double, 3>> ks_start;  // default: the volume's own k_s
    std::optional<std::array<double, 3>> contrast_start;  // default: the volume's own contrast
    double s_tolerance = 1.5;   // |ΔS_material| goal of --fit contrast, gray levels
    // --fit contrast may raise the density scale where the contrast alone
    // would have to clip many voxels (docs/design.md, "Contrast"); false
    // keeps the volume's own.
    bool fit_density = true;
    int width = 0;              // fitting renders: 0 = a quarter of the camera's width (at least 32)
    int spp = 0;                // 0 = chosen by the first fitting render, from kFirstFitSpp
    double noise = 0.3;         // standard error of A, gray levels, the chosen spp must reach
    double error = 0.4;         // and the estimated relative error (per pixel)
    int spp_max = 4096;         // the most the first fitting render doubles to
    // Samples per pixel of the renders --fit contrast reads S_material from
    // (FitSession::spread_spp); 0 = as many per image as a fitting render,
    // raised kMaxSpreadSppGain times where that hides a channel's S and
    // that many would show it.
    int spread_spp = 0;
    int max_renders = 24;
    double k_max = 4.0;         // FitLimits::k_max; k_min follows from the volume
    float exposure = 0.f;       // 0 = from the renders at both k_s bounds
    // A start from another fit's outcome (FitStart above; --fit contrast
    // only).
    std::optional<FitStart> start;
    // Stop where a step in density scale reaches its ceiling
    // (at_density_ceiling), before any render there: the stone sharpened by
    // kDefaultSharpen then takes the search on from that point (sharpening_for,
    // app/pipeline.h), where before it fitted the unsharpened stone to the
    // end first and started again from its outcome (docs/design.md,
    // "Sharpening").
    bool stop_at_density_ceiling = false;
    // Stop also where the search's first step in density scale rises by
    // the whole factor the stone's spread asks for (not capped at a step's
    // most), short of the ceiling: the density then stays short of it
    // (unsharpened, the cow and Onyx010's vase converged there without
    // another rise), where sharpening_for chooses kSharperStone, whose fit
    // takes the search on from that point.
    bool stop_at_first_rise = false;
    void validate() const;      // throws jade::Error naming the flag
};

// The fewest renders --fit contrast may be given: 2 at the k_s bounds, then
// steps of a render and its shading render (and a render at the fitting size
// when S is measured at the final one).
constexpr int kMinContrastRenders = 6;

// The most --fit contrast raises the density scale, as a factor of the
// volume's own (docs/design.md, "Contrast").
constexpr double kMaxDensityGain = 8.0;

// One fitting render: a row of fit.csv.
struct FitRecord {
    int iteration = 0;
    double seconds = 0.0;  // since fitting began
    int spp = 0;
    std::array<double, 3> ks{}, a_photo{}, a_render{}, a_sigma{}, delta{}, distance{};
    std::array<double, 3> contrast{1, 1, 1};
    double density_scale = 0.0;                    // OpticalParams::density_scale of the render
    double sharpen = 0.0;                          // the volume's sharpening (NoiseParams::sharpen)
    std::array<double, 3> s_photo{}, s_render{};   // spread S of the levels (fit/appearance.h)
    // S_material (fit/display.h) and the photo's S at the scale of its blocks
    // (fit/appearance.h); -1 where no shading render was made.
    std::array<double, 3> s_material{-1, -1, -1}, s_photo_scaled{-1, -1, -1};
    // The render noise's share taken out of S_material (MaterialSpread::noise).
    std::array<double, 3> s_material_noise{-1, -1, -1};
    // A at the final render's size, from --fit contrast's renders there
    // (extrapolated_brightness); -1 where none was made.
    std::array<double, 3> a_final_size{-1, -1, -1};
    // The share of the object's pixels at the final size whose clip at white
    // the noise decides (noise_clipped_share of the same renders as
    // a_final_size); -1 where none was made.
    std::array<double, 3> noise_clipped{-1, -1, -1};
    double structure = -1.0;                       // structure distance render → photo
    double structure_error = 0.0;                  // its standard error from the render's noise
    // The dominant orientation (degrees from the image's horizontal, in
    // [0, 180)) and its strength (0 isotropic to 1), of the photo and of the
    // render's object pixels (TextureSpectrum::orientation, strength).
    double orientation_photo = 0.0, orientation_render = 0.0, strength_photo = 0.0, strength_render = 0.0;
    // Shares of the render's object pixels at display level 0 and 255 (a
    // render that clips has a brightness that is only a bound).
    std::array<double, 3> at_black{}, at_white{};
    bool shading = false;                          // a render of the mean medium (contrast 0), not a fit step
    // Measured on a step's renders at the final size, box-downsampled to the
    // fitting size (box_downsampled): the row of a render that was not made.
    bool from_final_size = false;
};

struct FitOutcome {
    std::array<double, 3> ks{};           // fitted: the best found per channel
    std::array<double, 3> ks_start{};
    std::array<double, 3> contrast{1, 1, 1}, contrast_start{1, 1, 1};
    // The density scale fitted (--fit contrast; the volume's own otherwise)
    // and the volume's own, where the fit started.
    double density_scale = 0.0, density_scale_start = 0.0;
    // The most the fit could raise it to: kMaxDensityGain times the volume's
    // own, or a start's ceiling (FitStart).
    double density_scale_max = 0.0;
    // S_material and the photo's S at the same scale (the final render's
    // pixels, in blocks of material_block) at the chosen k_s and contrast
    // (--fit contrast only; -1 otherwise).
    std::array<double, 3> s_material{-1, -1, -1}, s_photo{-1, -1, -1};
    int material_block = 0;               // final-render pixels per side of the blocks S_material is taken over
    int spread_spp = 0;                   // samples per pixel of the renders S_material is read from
    // The count the first step rendered at where S_material hid in its noise
    // and the fit raised spread_spp (kMaxSpreadSppGain); 0 where it did not.
    int spread_spp_raised_from = 0;
    // The --fit-spread-spp at which every channel whose contrast was not
    // fitted would show its S (spp_for_noise; the largest of theirs); 0
    // where every channel's was fitted, or no count would do.
    int spread_spp_advised = 0;
    std::array<ChannelState, 3> state{};
    std::array<std::string, 3> reason;    // why a channel stopped unconverged
    std::vector<std::string> warnings;    // what a fit leaves short that is not a channel's failure
                                          // (a render that clips, a contrast the noise hid)
    bool converged = false;
    // Stopped where a step in density scale reached its ceiling
    // (FitOptions::stop_at_density_ceiling): not converged; ks and contrast
    // are the point the search would have rendered next, at density_scale,
    // the ceiling (start_from takes it on from there).
    bool stopped_at_density_ceiling = false;
    // Stopped where the first step in density scale met the stone's need
    // short of the ceiling (FitOptions::stop_at_first_rise), likewise.
    bool stopped_at_first_rise = false;
    // Per channel, --fit contrast searched the contrast (false where the
    // renders' noise hid S_material: FitSession::choose_spread_block).
    std::array<bool, 3> contrast_fitted{};
    float exposure = 1.f;                 // given, or found from the bounds
    bool exposure_matched = false;
    FitLimits limits;
    std::vector<FitRecord> records;
    // Fitting renders made: the records that are renders of their own (not
    // from_final_size), and --fit contrast's renders at the final size for
    // S_material (FitSession::spread_spp), two a step.
    int renders = 0;
    int spp = 0, width = 0, height = 0;   // of the fitting renders
    // dA/dk_s per channel near the fitted k_s (gray levels per unit), as the
    // fit last measured it; 0 when it measured none.
    std::array<double, 3> brightness_slope{};
    double estimated_error = 0.0;         // of the first fitting render
    double seconds = 0.0;
};

// A fit's outcome as the start of another (FitOptions::start).
FitStart start_from(const FitOutcome& fit);

class FitSession {
public:
    // Everything is referenced, not copied: it must outlive the session (the
    // volume's optical parameters are copied: the fitted ones may be set on
    // it after run()).
    FitSession(const MaterialVolume& volume, const Scene& scene, const CameraParams& camera,
               const RenderSettings& settings, const Photo& photo, const FitOptions& options);
    // The smallest k_s per channel: σ_s = v·d_s + k_s reaches 0 in the lowest voxel.
    const FitLimits& limits() const { return limits_; }
    // A fitting render at `ks` and `contrast` with `spp` samples per pixel.
    RenderResult render_at(const std::array<double, 3>& ks, const std::array<double, 3>& contrast, int spp) const;
    FitOutcome run(Progress* progress = nullptr);
    // The fitting renders are a quarter of the final render's width: at full
    // size the material's finer structure and the highlights' clipping
    // lower A (sRGB is concave; the demo's blue by 2.3 levels from 128² to
    // 512²). The change of A with size, added to the fitted ΔA, is the ΔA
    // expected at full size. --fit contrast rendered every step at full
    // size: A there (extrapolated_brightness) is the foresight, and less the
    // step's fitting-size A gives the change at no cost; k_s's secant steps
    // are then taken with renders at full size too (as many samples per
    // image as a fitting render, the steps' random numbers). Otherwise
    // renders at the outcome's k_s, contrast and density scale at both
    // sizes, each with `spp` samples per pixel, give the change (their
    // noise, alike per pixel, biases both alike), and the steps are taken at
    // the fitting size toward the photo's A less it. Where a channel is
    // foreseen off by 0.4 of the tolerance or more (the foresight's own
    // error is up to 0.5 levels), k_s moves by secant steps (at most 3
    // renders) until the ΔA expected at full size is within that
    // (docs/design.md, "The fit"). Call after run().
    struct FinalBrightness {
        std::array<double, 3> size_change{};  // A at full size less A at the fitting size
        std::array<double, 3> delta{};     // ΔA expected at full size at the fitted k_s
        std::array<double, 3> ks{};        // the k_s the check chose (the fitted one where ΔA was near enough)
        std::array<double, 3> expected{};  // ΔA expected at full size at those
        bool from_fit = false;             // the change of A from the fit's own renders at full size
        int spp = 0;                       // samples per pixel of the full-size renders it was taken from
        int renders = 0;                   // fitting renders the steps took
        // A at full size read from the final render's first `spp` samples
        // (full_size below), not from a render of the check's own.
        bool from_final_render = false;
        // What chose between the fit's renders and a full-size render, read
        // on the fit's last render at the fitted k_s (brightness_from_fit):
        // per channel the share of its object pixels at 255 and the share
        // near white by the noise of its renders at the final size (-1
        // where none was made).
        std::array<double, 3> white_share{}, noise_clipped{-1, -1, -1};
    };
    // `full_size`, where the caller has it: the final render's first `spp`
    // samples per pixel of the volume at the fit's outcome, the object
    // alone (less the backdrop's share, as the fit's renders see it:
    // ProgressiveRender::run_to), read as the render at full size instead of
    // one of the check's own; the final render carries on from those
    // samples where k_s stays. Its medium's majorant is the final render's,
    // not the fit's shared one: the same A, other noise.
    // Needed only where the change of A is not the fit's own:
    // brightness_from_fit() false.
    FinalBrightness final_brightness(int spp, const Film* full_size = nullptr) const;
    bool brightness_from_fit() const;

private:
    RenderResult fitting_render(const std::array<double, 3>& ks, const std::array<double, 3>& contrast);
    SplitFilms split_render(const PinholeCamera& camera, const std::array<double, 3>& ks,
                            const std::array<double, 3>& contrast, int spp);
    int spread_spp() const;
    struct BrightnessStart;
    BrightnessStart brightness_start() const;
    struct StepRenders;
    StepRenders step_renders(const std::array<double, 3>& ks, const std::array<double, 3>& contrast);
    FitRecord* rendered_at(const std::array<double, 3>& ks, const std::array<double, 3>& contrast);
    int step_cost() const { return spread_at_final_size_ && box_factor_ == 0 ? 3 : 2; }
    template <class How>
    auto with_medium(const PinholeCamera& camera, const std::array<double, 3>& ks,
                     const std::array<double, 3>& contrast, int spp, How how) const;
    std::shared_ptr<const LightGuide> light_guide(const Scene& scene, const PinholeCamera& camera, int spp) const;
    FitRecord& record(const std::array<double, 3>& ks, const std::array<double, 3>& contrast, const Film& film);
    void bracket(FitDriver& driver);
    void fit_from_bounds();
    void finish(const FitDriver& driver);
    struct ContrastSearch;
    void fit_contrast(const std::array<double, 3>& brightness_slope);
    MaterialSpread choose_spread_block(ContrastSearch& search, const StepRenders& step);
    bool raise_spread_spp(ContrastSearch& search);
    std::string hidden_spread_warning(int c, const QuietBlock& q, double g, const SpreadReading& r, int spp) const;
    void finish_contrast(const ContrastSearch& search);
    void contrast_step(ContrastSearch& search, int channel, double delta, double s, double a_sigma);
    bool raise_density_scale(ContrastSearch& search, const std::array<double, 3>& s_photo);
    void measure_density_exponent(ContrastSearch& search) const;
    double spread_elasticity(int channel, double g) const;
    void mark_clipped_channels();
    const FitRecord* final_record(int c) const;
    std::array<double, 3> brightness_slopes() const;
    double k_min_at(int channel, double contrast) const;
    FitLimits k_search_limits() const;
    void set_density_scale(double density_scale);
    int fitting_renders() const;

    const MaterialVolume& volume_;
    const Scene& scene_;
    const Photo& photo_;
    FitOptions options_;
    std::array<int, 3> lowest_level_;   // per channel, over the volume's voxels
    LevelHistograms level_histograms_;  // the volume's voxels per level and channel
    // The volume's optical parameters as given: the fit varies k_s, the
    // contrast and the density scale from them (the volume's levels are
    // read, its parameters may be changed once the session ran).
    OpticalParams optics_;
    FitLimits limits_;
    PinholeCamera camera_;
    RenderSettings settings_;
    RgbHistogram photo_histogram_;
    TextureSpectrum photo_spectrum_;
    double pixels_per_side_;   // of the fitting renders, where the object stands
    // --fit contrast measures S_material where a person sees it: at the
    // final render's size, through its camera, with as many samples per
    // image as a fitting render (spread_spp). Transport blurs structure
    // finer than a mean free path, and the material matched in the fitting
    // renders' 4× larger pixels was 5–7 levels short of the photo's spread
    // at the final render's scale (docs/design.md, "Contrast").
    bool spread_at_final_size_;      // the final camera is larger than the fitting renders'
    PinholeCamera final_camera_;
    const PinholeCamera& spread_camera() const { return spread_at_final_size_ ? final_camera_ : camera_; }
    double spread_pixels_per_side_;  // of spread_camera()
    // The final camera's width and height over the fitting camera's where
    // both are that whole multiple (a final-size render then holds a
    // fitting-size one: box_downsampled), else 0.
    int box_factor_;
    int spread_renders_ = 0;         // renders at the final size (two a step; not rows of fit.csv)
    int spread_spp_raised_ = 0;      // raise_spread_spp's count; 0 = spread_spp()'s own
    // The density scale of the fitting renders and the majorant they share
    // (that of k_s = k_max at every contrast, at this density scale).
    double density_scale_;
    Spectrum shared_majorant_;
    // The light guides the renders traced (render/light_estimator.h,
    // light_guide_for), by what makes one differ within a session: its ray
    // count (the camera's samples) and the medium's majorant (the guide's
    // attenuation). Renders that share both share the guide, as traced.
    struct TracedGuide {
        std::uint32_t photons;
        Spectrum majorant;
        std::shared_ptr<const LightGuide> guide;
    };
    mutable std::vector<TracedGuide> guides_;
    mutable std::mutex guides_mutex_;
    Stopwatch clock_;
    Progress* progress_ = nullptr;
    FitOutcome outcome_;
};

// The sharpening of the levels (volume/sharpen.h) a fit's outcome asks for,
// and why (docs/design.md, "Sharpening"). The fit shows how far light
// travels in the stone: where the density scale stayed at the volume's own,
// it spreads over many voxels and a sharpened structure blurs out on the
// way (Marble01 at 20, sharpened fourfold, showed nothing more): none. Where
// the fit raised the density scale short of its ceiling, by a step of
// density at least, kSharperStone: the density can still rise to pay for
// the spread a sharper stone moves into the bands transport blurs. At the
// ceiling, kDefaultSharpen: the demo's blue, whose contrast had nothing
// left, converged there and not at kSharperStone; so also for a fit
// stopped at the ceiling (FitOptions::stop_at_density_ceiling), and
// kSharperStone for one stopped at its first rise short of it
// (FitOptions::stop_at_first_rise). None where the fit did not converge.
struct SharpeningChoice {
    double amount = 0.0;
    std::string why;
};
SharpeningChoice sharpening_for(const FitOutcome& fit);

// Whether the fit stopped for a sharper stone's fit to take its search on
// (at the density scale's ceiling, or at its first rise).
bool stopped_for_sharper_stone(const FitOutcome& fit);

// Whether the density scale can rise no further: a step from it to its
// ceiling would be smaller than the least worth taking.
bool at_density_ceiling(double density_scale, double density_scale_max);

// The first dS/dg of a channel's --fit contrast search, at contrast g
// where S_material reads s and the photo's S is s_photo: S/g times the
// contrasted levels' elasticity (S grows in proportion to g while no voxel
// clips), s_photo (at least 1) where s is the rounding of a flat material,
// and in either case at least the slope that brings s_photo at the
// contrast ceiling (docs/design.md, "Contrast").
double first_spread_slope(double s, double g, double elasticity, double s_photo);

}  // namespace jade
