#pragma once
// The render seen as the photo's camera would have recorded it (paper §5.4;
// docs/design.md, "Display space"): its brightness A(κ) per channel in the
// photo's 8-bit display levels, and the exposure that brings it there.
//
//   A(κ) = Σ_i i · H(i, κ), gray levels 0..255, over the object's pixels
//   ΔA(κ) = A_render(κ) − A_photo(κ); goal |ΔA(κ)| < Δd = 1 gray level
//
// Brightness grows with k_s (more scattering, higher albedo), so a render
// brighter than the photo lowers k_s (the paper's Algorithm 2 prints the sign
// reversed; its text is right).

#include "jade/render/film.h"
#include "jade/render/renderer.h"
#include "jade/volume/histogram.h"
#include "jade/volume/photo.h"
#include "jade/volume/texture_spectrum.h"

#include <array>
#include <string>

namespace jade {

// The render as the photo's camera would have recorded it: linear radiance ×
// exposure → sRGB → 8-bit, over the pixels the object covers (coverage ≥ 0.5).
struct DisplayStatistics {
    RgbHistogram histogram;
    // A(κ) of the histogram, less the bias the pixels' noise puts into it
    // (the concave sRGB curve lowers the mean level of a noisy pixel by
    // ½·|srgb''|·Var, estimated from the film's per-pixel variance), so that
    // A estimates the converged render's value whatever the sample count.
    std::array<double, 3> a{};
    std::array<double, 3> a_sigma{};  // standard error of A(κ) from the film's per-pixel variance
    // S(κ): the spread of the levels over the object, less the part the
    // pixels' noise adds (S² = variance of the levels − mean per-pixel noise
    // variance), so that it estimates the converged render's spread.
    std::array<double, 3> s{};
    // The object's luma in display levels (mask = object pixels), and the
    // per-pixel noise variance of that luma, for its texture spectrum. The
    // channels' noise is taken as fully correlated (one path carries all
    // three), which bounds the luma's noise from above.
    GrayImage luma;
    double luma_noise_variance = 0.0;
    // The same luma from two independent halves of the samples (replicates
    // 0–1 and 2–3, render/film.h; width 0 unless LumaHalves::Measure, and
    // while a replicate holds less than a turn of the heroes): their
    // cross-spectrum is the render's structure with no noise to subtract
    // (volume/texture_spectrum.h).
    std::array<GrayImage, 2> luma_halves;
    std::size_t pixels = 0;
};
// Whether display_statistics also makes the luma's two halves (a few tens of
// milliseconds at 512²): only the renders whose structure is measured need them.
enum class LumaHalves { Skip, Measure };
DisplayStatistics display_statistics(const Film& film, float exposure, LumaHalves halves = LumaHalves::Skip);

// A(κ) of a render given in two halves, extrapolated to infinitely many
// samples. The noise's bias of the mean level falls about as 1/spp (the
// demo's red at 512²: 8.8, 4.2, 2.0 and 0.9 levels low at 8, 16, 32 and 64
// spp), so Richardson's extrapolation from the whole (n samples) and the
// halves (n/2) removes most of it: A∞ ≈ 2·A(n) − A(n/2), on the raw mean
// levels. Not on display_statistics' A: the delta method's correction there
// rests on each film's own estimate of its pixels' variance, which the halves
// (two replicates each) and the whole (four) make differently, so the
// correction does not fall as 1/spp and the extrapolation overshot (the
// demo under the delta light, 16 spp: red 1.3–1.5 levels high, on the raw
// means 0.35–0.5; docs/design.md, "The fit").
std::array<double, 3> extrapolated_brightness(const SplitFilms& render, float exposure);

// Per channel, the share of the object's pixels whose clip at white the
// render's noise decides: one of its two independent halves shows the pixel
// at level 255 and the other below it. A pixel far above white is at 255 in
// both, one far below in neither. Near white, a rare bright sample's energy
// beyond white is lost at the clip, a loss that falls slower than 1/spp, so
// extrapolated_brightness reads such a render low (the brightness check's
// rule, FitSession::brightness_from_fit).
std::array<double, 3> noise_clipped_share(const SplitFilms& render, float exposure);

// d(display level)/d(linear value) of the sRGB curve at `linear` (0 at and
// beyond 1, where the level is clipped): the delta method's factor from a
// linear pixel's noise to its level's.
double level_slope(double linear);

// S_material(κ): the spread of levels the material itself puts into a render
// (docs/design.md, "Appearance"). The photo is a flat scan, the render a lit
// object whose shading (the light's falloff, the rim, the highlight) spreads
// its levels as much as the stone does; S of the whole render cannot tell
// the two apart. `shading` is the same render with the volume's mean medium
// (contrast 0) under the same random numbers. Each pixel is flattened,
// render / shading, scaled so that the flattened image has the render's
// mean level A (where the renders share paths, their noise cancels in the
// ratio); pixels whose shading is below 5 % of its mean (the dark rim) are
// left out: their ratio says nothing. The flattened image is averaged over
// blocks of block × block pixels (a fitting render's per-pixel noise is as
// large as the stone's contrast; a block's is block times smaller) and S is
// the spread of the blocks' levels. Compare it with photo_spread at the
// block's scale.
//
// What noise the ratio and the blocks leave still widens the spread, and
// the more so the noisier the renders: the light's rare paths are heavy-
// tailed, and neither the film's per-pixel variance nor the shared paths
// account for them. Both renders come in two independent halves
// (render_halves); the blocks' levels of the halves' flattened images, L₁
// and L₂, share the image and not the noise, so Cov(L₁, L₂) over the blocks
// is the spread of the image the halves share. That image is still biased
// by the noise: a block's level is a curve (sRGB, and the ratio to the
// shading) of noisy means, whose expectation moves by about the noise's
// variance, so the bias falls as 1/n with n samples per half (the demo at
// 512²: S from halves of 8 samples 1.5, 1.1 and 0.4 levels below S from
// halves of 128). Given the quarters too (render_quarters), S² is
// Richardson's extrapolation of the two to infinitely many samples:
// 2·Cov(halves) − the mean Cov over the six pairs of quarters (measured:
// within 0.5 levels of the 128-sample S at 8 samples a half, four seeds).
// Subtracting Var(L₁ − L₂)/4 from the whole render's spread instead was
// tried: with noise as large as the spread the sRGB curve makes it read
// 12 % low.
struct MaterialSpread {
    std::array<double, 3> s{};      // the spread, the noise's share taken out
    std::array<double, 3> noise{};  // the noise's share of the whole render's spread: √(S_whole² − S²), levels
    // How far S² scatters from one render to the next, read from this one:
    // the standard deviation of the covariances of its six pairs of
    // quarters (levels²; 0 without quarters). S² (2·the halves' covariance
    // − the quarters' mean) shares their data and scatters by about 0.8 of
    // it (synthetic noise over 16 renders: 7.8 against 10.2). Heavy-tailed
    // noise included, which a Gaussian bound from the noise and the number
    // of blocks would miss.
    std::array<double, 3> scatter{};
};
MaterialSpread material_spread(const SplitFilms& render, const SplitFilms& shading, float exposure, int block);

// The flattened render itself as an image (above: render / shading at the
// render's mean level), averaged over block × block pixels: the stone as a
// flat scan would show it, to hold against the photo at the same scale
// (fit/appearance.h, compare_material). Its foreground: the blocks
// flattened in every channel.
Photo flat_render(const Film& render, const Film& shading, float exposure, int block = 1);

// The photo's own stone under a render's shading: each object pixel of the
// shading render (the volume's mean medium, fit/appearance.h) times the
// photo's linear colour over that pixel's footprint, the photo laid flat
// over the image at the render's scale (`render_pixels_per_side` render
// pixels to one cube side, which the photo spans) and repeated, each channel
// then scaled so that its mean level is the photo's A, as the fit matches
// it. Its histogram against the photo's is the D a render whose material
// were the stone itself would reach under that light and on that form: the
// part of the whole render's D that the shading holds. Pixels whose
// footprint is mostly the photo's background are left out.
Photo shaded_photo(const Photo& photo, const Film& shading, float exposure, double render_pixels_per_side);

// The least D(κ) against the photo that any material reaches under a shading
// render, per channel, at the photo's A: the render taken as shading ×
// material pixel by pixel (the flattening's model, above), the material's
// levels independent of where the shading falls. The render's histogram is
// then a mixture of the histograms of a·shading over the material's
// multipliers a, and the best mixture whose mean level is the photo's A (as
// the fit makes the render's) is a least-squares fit on the simplex
// (core/simplex_least_squares.h) over a log grid of a, about 1 % apart,
// from all pixels at level 0 to all at 255. The value is the fit's certified
// lower bound, within 1 % (or 10⁻⁵) of the best mixture found: no material
// whose levels are laid out independently of the light, the photo's own
// stone included (shaded_photo), scores below it at the photo's A (up to the
// grid's half-level rounding). Where unlit pixels (shading 0) keep every
// material's A below the photo's, at the nearest A any material reaches. −1
// where the shading or the photo has no object pixel.
std::array<double, 3> least_material_distance(const Photo& photo, const Film& shading, float exposure);

// The same over the materials whose own histogram of levels lies within
// `material_d` of `material_photo` (§5.4's D, per channel; a render's
// measured D_material and the photo's block histogram it was taken
// against, say): the least whole-render D that a material as like the
// photo's stone as that one reaches under the shading. A material's level in
// the model is the one the flattened render shows (render over shading,
// scaled to the render's A): its multiplier against the one whose render
// alone has the photo's A, which shows A. A ceiling on a convex distance
// leaves a convex problem; the value is a certified lower bound in the
// model by Lagrangian duality (core/simplex_least_squares.h,
// simplex_least_squares_near), and like least_material_distance's it bounds
// a render only as far as the render is shading × material: on the bunny
// under the demo photo the render's own red D (0.0038) came under both
// (0.0043 for any material, 0.0047 for one as like the stone), its green
// under the second (0.0012 against 0.0014). Without the ceiling the least-D
// material can be nothing like the stone: on the demo's vase red's is 91 %
// within 16 levels and 9 % some 40 levels brighter (docs/design.md,
// "Appearance"). −1 as above, and in a channel whose material D is negative
// (not measured).
std::array<double, 3> least_material_distance_as_near(const Photo& photo, const Film& shading, float exposure,
                                                      const std::array<double, 3>& material_d,
                                                      const RgbHistogram& material_photo);

// The block for material_spread: the side, in pixels, over which a render of
// this estimated relative error per pixel averages to 0.1 (at most
// kMaxMaterialBlock).
constexpr int kMaxMaterialBlock = 8;
int material_block(double relative_error);

// The exposure that gives the render's object pixels the photo's mean linear
// luminance (Rec. 709 weights): the photo's absolute exposure is unknown, so
// by default the fit matches it once, at its first render, and lets k_s
// match each channel from there.
float matching_exposure(const Film& film, const Photo& photo);

// The exposure at which the render's A(κ) in channel c equals `target`
// (A grows with exposure; found by bisection on its logarithm). 0 or
// infinity when even 10^-4 or 10^4 cannot reach it.
double exposure_for_brightness(const Film& film, int channel, double target);

// The exposure for fitting from renders at both k_s bounds: every channel c
// can reach the photo's A_c at exposures from the one where the k_max render
// matches it to the one where the k_min render does (in display space, as A
// is measured). Returns the geometric middle of the range all channels
// share, within [10^-4, 10^4]; when the ranges do not overlap, the middle of
// the conflict (the channels that cannot reach the photo are then reported by
// the driver). Always finite and positive.
double exposure_in_reach(const Film& at_k_min, const Film& at_k_max,
                         const std::array<double, 3>& photo_a);

// Mean linear RGB of the photo's foreground (sRGB decoded) and of the
// object's pixels in a render (coverage >= 0.5, divided by coverage).
Spectrum photo_mean_linear(const Photo& photo);
Spectrum object_mean_linear(const Film& film);

}  // namespace jade
