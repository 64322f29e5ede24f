#pragma once
// The spatial structure of a texture, the part of "looking like the photo"
// that histograms do not see (docs/design.md, "Structure"): how its variance
// is spread over spatial frequencies (the radially averaged power spectrum),
// and whether it runs along one direction (bands, veins).
//
// Frequencies are in cycles per cube side, the length a volume slice spans,
// so a photo (which spans the side), a volume slice and a render (whose pixel
// footprint is known) are compared at the same physical scale. Bands are
// half an octave wide, from 1 to 1024 cycles per side.

#include <array>
#include <cstdint>
#include <vector>

namespace jade {

// One channel of an image and which pixels belong to the texture; row 0 is
// the top row as displayed.
struct GrayImage {
    int width = 0, height = 0;
    std::vector<float> values;          // row-major
    std::vector<std::uint8_t> mask;     // 1 = part of the texture; empty = all pixels
    bool inside(int x, int y) const { return mask.empty() || mask[std::size_t(y) * width + x]; }
};

// The largest axis-aligned square of texture pixels: {x0, y0, side}; side 0
// when there is none. The spectrum is measured there, so that the edges of an
// object's silhouette do not count as structure.
std::array<int, 3> largest_inside_square(const GrayImage& image);

struct TextureSpectrum {
    static constexpr int kBands = 20;
    // Lower edge of band b: 2^(b/2) cycles per side.
    static double band_low(int b);
    // Share of the measured variance per band; < 0 where the image cannot
    // measure the band (below 2 cycles across the square, above Nyquist).
    std::array<double, kBands> power{};
    // The standard error of each share from the images' noise (of a
    // cross-periodogram, or of a periodogram less a noise floor; 0 for an
    // image without noise), and whether the band is below_noise: its power
    // under kDetection standard errors, the least the noise lets one see
    // there. The distance takes the share as measured all the same; the
    // flags say where it is the noise's draw (docs/design.md, "Appearance":
    // bands under the noise).
    std::array<double, kBands> error{};
    std::array<bool, kBands> below_noise{};
    // Three standard errors: at two, 2.3 % of the bands of pure noise read as
    // structure, in a quarter of the spectra of 12 bands.
    static constexpr double kDetection = 3.0;
    // The direction the structure runs along, degrees counterclockwise from
    // the displayed image's horizontal, in [0, 180); and how strongly, from 0
    // (isotropic) to 1 (every frequency along one direction).
    double orientation = 0.0;
    double strength = 0.0;
    // Local coherence, 0 to 1: how parallel the image's gradients are within
    // blocks a 32nd of a side wide (energy-weighted), high for bands and veins
    // even where they wander, low for grain and blobs.
    double coherence = 0.0;
    // Orientation defects, 0 to 1: the share of the cells between four
    // neighbouring blocks' centres around which the blocks' orientation turns
    // by half a turn (a Poincaré index of ±½, as at a fingerprint's cores and
    // deltas). Few where long layers fold; many where layers end, fork or
    // close into rings, and in grain (docs/design.md, "Structure").
    double defects = 0.0;
    int square = 0;                     // side of the measured square, pixels
    int measured_bands() const;
    int bands_below_noise() const;      // of the measured ones
};

// The spectrum of the largest square of texture pixels, Hann-windowed, mean
// removed. `pixels_per_side`: image pixels per cube side. `noise_variance`: the
// per-pixel variance of white noise on the values (a Monte Carlo render's),
// subtracted from every frequency so that it does not count as structure.
TextureSpectrum texture_spectrum(const GrayImage& image, double pixels_per_side,
                                 double noise_variance = 0.0);

// The structure two noisy images of one texture share: the same bands from
// the cross-periodogram Re(A·conj(B)) over the largest square inside both.
// Where their noise is independent (two halves of a render's samples) it
// averages out of the bands whatever its distribution, which a subtracted
// floor cannot promise for the heavy-tailed noise of a Monte Carlo render.
// The coherence comes from the product of their gradients: the noise
// averages out of each block's tensor, though not wholly out of its
// eigenvalues' difference.
TextureSpectrum texture_cross_spectrum(const GrayImage& a, const GrayImage& b, double pixels_per_side);

// The root mean square difference of two spectra's log10 power shares over
// the bands both measure, each renormalised to those bands: 0 for the same
// structure at the same scale, 0.3 for a factor of two per band. Negative
// when they share fewer than two bands. Bands under an image's noise
// (TextureSpectrum::below_noise) count as measured: where many are, the
// distance moves with the noise's draw.
double structure_distance(const TextureSpectrum& a, const TextureSpectrum& b);

// The standard error of structure_distance(a, b) from the spectra's noise:
// the standard deviation of the distance over kStructureErrorDraws draws of
// both spectra, each measured band's share moved by its standard error times
// a standard normal (held at 0 from below, as a measured share is), from a
// fixed stream. 0 for spectra without noise (a photo, a volume slice). Two
// renders of one scene with other seeds differ by about √2 times it: a
// difference of distances under two or three of it is the noise's draw
// (docs/design.md, "Appearance": the distance's error).
double structure_distance_error(const TextureSpectrum& a, const TextureSpectrum& b);
// Enough that the error is known to about 3 %, in well under a millisecond.
constexpr int kStructureErrorDraws = 512;

// `s` measured only in the bands `other` measures too: two spectra held
// against a third over the same bands, whatever each image could resolve.
TextureSpectrum common_bands(const TextureSpectrum& s, const TextureSpectrum& other);

// The smaller angle between two orientations (degrees, modulo 180).
double orientation_difference(double a, double b);

}  // namespace jade
