#pragma once
// What a person compares when they hold a render beside the photo
// (docs/design.md, "Appearance"), all in display levels over the object's
// pixels: per channel the brightness A (§5.4), the spread S and the histogram
// distance D; and the structure, through the texture spectra of the two
// lumas at the same physical scale (volume/texture_spectrum.h).

#include "jade/core/bounds.h"
#include "jade/fit/display.h"
#include "jade/render/camera.h"
#include "jade/volume/histogram.h"
#include "jade/volume/photo.h"
#include "jade/volume/texture_spectrum.h"

#include <array>

namespace jade {

struct Appearance {
    std::array<double, 3> a_photo{}, a_render{}, s_photo{}, s_render{}, d{};
    TextureSpectrum photo, render;
    double structure = -1.0;   // structure_distance(render, photo); < 0 when they share too few bands
    double structure_error = 0.0;  // its standard error from the render's noise (structure_distance_error)
};

// Render pixels per cube side where the object stands: the cube side over one
// pixel's footprint at the distance of the cube's centre.
double render_pixels_per_side(const CameraParams& camera, const Cube& cube);

// The photo's texture spectrum (its luma over the foreground; the photo spans
// one cube side).
TextureSpectrum photo_spectrum(const Photo& photo);

// The photo's spread S per channel at a render's pixel scale: the photo is
// box-averaged (in linear light) over blocks as wide as one render pixel's
// footprint on the cube before S is taken, so that the texture finer than a
// render pixel, which the render cannot show, does not count. At the photo's
// own scale or finer it is the histogram's spread.
std::array<double, 3> photo_spread(const Photo& photo, double render_pixels_per_side);
// The histogram of those block levels.
RgbHistogram photo_block_histogram(const Photo& photo, double render_pixels_per_side);

// The block a material measure is read over: the smallest from `first` on
// (up to kMaxMaterialBlock) over which the render's noise (material_spread's
// share) is at most `share` times the photo's spread at that scale in every
// channel, else kMaxMaterialBlock; with the spread measured there and the
// photo's. A near-white stone needs larger blocks than its render's relative
// error says (material_block): near white a relative error is twice as many
// levels as at mid-grey, and such a stone spreads few (Marble021: noise 26
// levels over one pixel against the photo's 4.5).
struct QuietBlock {
    int block = 1;
    bool quiet = false;                     // false: kMaxMaterialBlock, and still noisier than `share`
    MaterialSpread spread;                  // material_spread over `block`
    std::array<double, 3> photo_spread{};   // photo_spread at `block`'s scale
};
QuietBlock quiet_block(const Photo& photo, const SplitFilms& render, const SplitFilms& shading, float exposure,
                       double render_pixels_per_side, int first, double share);

// The most noise, as a multiple of the photo's spread over the same
// blocks, that --fit contrast reads S_material through (quiet_block, read_spread). The
// halves' covariance takes the noise's bias out, not its scatter, and the
// light's heavy-tailed paths make that scatter several times the Gaussian
// estimate. Measured: on the demo at one pixel's blocks (red's noise 24–28
// levels against the photo's 13.5) the fit matched S to within 0.5 level of
// a 256-spp measurement; on Marble021 at one pixel (noise 26 against 4.5) S
// read 0 to 9 levels from one step to the next, at 8 (4.7 against 1.7) 0 to
// 21, and the contrast chased it to its cap. At 1 the demo's S is matched
// over 3-pixel blocks, where the photo spreads 2 levels less, and the fit
// stopped at a blurrier stone (density scale 80 against 105; the render's
// structure distance 2.04 against 1.45–1.55).
constexpr double kSpreadNoiseShare = 2.0;

// The most S² may scatter from one render to the next (MaterialSpread::
// scatter), as a share of the square of the larger of the photo's spread
// and the render's, for --fit contrast to search a channel's contrast. The
// noise's multiple alone (above) misses how few blocks there may be: on the
// vase under Marble021 (6-px blocks) the noise was 1.92–2.00 times the
// photo's spread and S² scattered by 0.28–0.38 of the photo's S²; S then
// read 2.7, 0, 6.4, 0 and 1.3 levels from step to step in green, whose
// contrast ran to 7.4. Where S held from step to step it scattered by 0.03
// or less (the demo), 0.045 (Marble01 on the same vase, 3-px blocks, four
// times as many) and 0.15 (Marble021's bunny with --fit-spread-spp 64,
// red: S read 1.9, 1.3 and 2.0). With six pairs the scatter is itself known
// to about 30 %, so the bound sits between 0.15 and 0.28.
constexpr double kSpreadScatterShare = 0.2;
// Below this scatter (levels²) S² is steady whatever the spreads: S near 0
// then wobbles by 0.1 level, far under the fit's S tolerance (1.5). A flat
// photo on a flat volume spreads nothing, and its S²'s scatter is rounding.
constexpr double kSpreadScatterFloor = 0.01;

// Whether the fit's renders show channel c's S_material over their block
// (FitSession::choose_spread_block): its noise at most kSpreadNoiseShare
// times, and S²'s scatter at most kSpreadScatterShare times the square of
// (or kSpreadScatterFloor), the larger of the photo's spread there, the
// render's, and the fit's S tolerance. Spreads under the tolerance are read
// as if at it: the fit needs S only to within the tolerance, and against a
// one-colour photo's spread of 0 any noise at all (0.02 levels on a dark one)
// was more than twice it, so the contrast was called hidden in the noise of a
// render that had none to speak of.
struct SpreadReading {
    double noise_limit = 0.0, scatter_limit = 0.0;
    bool quiet = false, steady = false;  // noise, scatter within their limits
    bool readable() const { return quiet && steady; }
};
SpreadReading read_spread(const MaterialSpread& spread, const std::array<double, 3>& photo_spread, int c,
                          double s_tolerance);

// Where even the largest block is not quiet: the samples per pixel at which
// the render's noise, `noise` at `spp`, falls to `limit`, taken to fall as
// spp^(-1/3), rounded up to a power of two times `spp`; 0 where none up to
// 2^20 would (a limit of 0: the photo spreads nothing there). Not as
// 1/√spp: below about 64 spp the shading render's common random numbers
// cancel more of the flattened render's noise, and the rare bright paths
// have not all shown up (README, "How the error falls"). On
// Marble021's fitted volume in the bunny (two seeds each, 8-px blocks, the
// render flattened by its shading as the fit takes it) 5.2 levels at 16
// spp, 3.2 at 64 (spp^-0.35), 1.7 at 256. Where the noise does fall as
// 1/√spp the count asked for is (noise / limit) times too many at most.
int spp_for_noise(int spp, double noise, double limit);

// What a shading render (the volume's mean medium: the light and the form
// alone) leaves of the whole render's D, against the photo as the whole
// render's D is taken: the photo's own stone laid under it (fit/display.h,
// shaded_photo; < 0 where no object pixel's footprint falls mostly on the
// photo's foreground), and the least any material reaches under it
// (least_material_distance: below the stone's, and a bound on every
// material whose levels do not follow the light). The shading's density
// scale is the caller's to record (bench fidelity --densities renders one
// volume's shading at several, docs/design.md, "Appearance").
struct ShadingReach {
    double density_scale = 0.0;
    std::array<double, 3> d_stone{-1.0, -1.0, -1.0}, d_least{-1.0, -1.0, -1.0};
    double seconds = 0.0;  // the shading render's and both distances' (the caller's to record)
};
ShadingReach shading_reach(const Photo& photo, const Film& shading, float exposure, double render_pixels_per_side);

// The material against the photo with the render's shading divided out
// (fit/display.h, flat_render): a flat scan of a stone has no
// shading, a lit object does, and A, S and D of the whole render measure
// both. Here the render and its shading render (the volume's mean medium,
// same random numbers), each in two independent halves (render_halves), are
// flattened and averaged over blocks in which the render's noise falls to
// 0.1 (material_block), and the photo is averaged over blocks of the same
// footprint on the cube. S_material and the structure are measured on what
// the halves share (material_spread, texture_cross_spectrum), so the
// render's noise is not counted as the stone's spread or as fine structure.
// A histogram cannot be taken from what two halves share, so the histogram
// distance D is of the merged halves' blocks, noise and all, over blocks
// large enough that the noise's spread is at most kDNoiseShare of the
// photo's at that scale in every channel (the noise then widens the
// histogram by 3 % at most): on a white marble whose photo spreads 7
// levels, the noise of a 256-spp render's pixel spread 8–10, and D of one
// pixel's blocks measured the noise more than the stone (docs/design.md,
// "Appearance").
struct MaterialAppearance {
    static constexpr double kDNoiseShare = 0.25;
    static constexpr int kMaxBlock = kMaxMaterialBlock;
    std::array<double, 3> s_material{}, s_photo{}, d{};
    // D over blocks of 1 to kMaxBlock pixels (d_by_block[b − 1]): methods
    // measured at different blocks compare at the larger of theirs.
    std::array<std::array<double, 3>, kMaxBlock> d_by_block{};
    int d_block = 1;            // the block of d: the smallest from `block` on where the noise is that small
    // The noise's spread over d_block's blocks and the photo's there,
    // levels (above kDNoiseShare of it where even kMaxBlock's blocks are
    // not that quiet: d_block is then kMaxBlock).
    std::array<double, 3> d_noise{}, d_photo_spread{};
    std::array<double, 3> s_noise{};  // the noise's share taken out of S_material, levels
    // The whole render's D that the shading alone leaves (shading_reach):
    // the photo's own stone's under the shading render, and the least any
    // material reaches there.
    std::array<double, 3> d_stone{}, d_least{};
    // And of the materials as like the photo's stone as this one: their
    // own histogram within `d` (D_material) of the photo's
    // (least_material_distance_as_near). Where it is above the whole
    // render's goal, only a material less like the stone reaches the goal,
    // as far as the render is shading × material (on the bunny under the
    // demo photo the render came 12–19 % under the model's bounds).
    std::array<double, 3> d_least_as_near{};
    // And the whole render's structure distance that the shading alone
    // leaves: that stone's (the cross-spectrum of the shading's halves,
    // each with the stone) against the photo's; < 0 as structure_distance.
    double structure_stone = -1.0;
    TextureSpectrum spectrum;   // of the flattened blocks' luma, noise taken out
    double structure = -1.0;    // structure_distance(spectrum, the photo's)
    double structure_error = 0.0;  // its standard error from the render's noise
    int block = 1;              // render pixels per block side
    std::size_t blocks = 0;     // render blocks in the histogram
};
MaterialAppearance compare_material(const Photo& photo, const SplitFilms& render, const SplitFilms& shading,
                                    float exposure, double render_pixels_per_side);

Appearance compare_appearance(const RgbHistogram& photo_histogram, const TextureSpectrum& photo_spectrum,
                              const DisplayStatistics& render, double render_pixels_per_side);

}  // namespace jade
