#pragma once
// Material distribution as noise (paper §4.1, Table 1): 3D simplex noise
// (Gustavson 2005, "Simplex noise demystified") summed as fractal Brownian
// motion over a cube of side s voxels.
//
//   Noise(x) = sum_{i=0}^{n-1} SimplexNoise(x * Fr_i) * Amp_i
//   Fr_0 = 1/s, Fr_{i+1} = 2 Fr_i,  Amp_0 = k, Amp_{i+1} = k Amp_i,  n = log2(s)
//
// Beyond the paper (docs/design.md, "Structure"): the base frequency may be
// f_0 cycles per side instead of one (Fr_0 = f_0/s), and the noise may be
// stretched by a factor r along a direction at `angle` in the slice plane and
// along z, so that slices show bands running at that angle and the solid is
// made of sheets, as layered stone is. f_0 = 1, r = 1 is the paper's fBm.
// With b > 0 bands the value is instead Perlin's marble (SIGGRAPH 1985),
// sin 2π b(w/s + a·Noise/bound): b layers per side across the angle,
// displaced by the fBm by up to a cube sides, so that slices show thin,
// sharp, continuous veins that wander as the fBm does.
// With `layers` (and b > 0) the sine is replaced by a one-dimensional fBm of
// the same warped coordinate, b·(w/s + a·Noise/bound), whose first octave
// varies over about 1/b of a side and whose octaves take the amplitude ratio
// k: layers of many thicknesses in packets, as sedimentary onyx is banded,
// where the sine's are all alike. The warp is then the paper's fBm
// (amplitude ratio 1/2, base frequency f_0) of three octaves, smooth, so the
// packets fold as a whole instead of breaking into a labyrinth.
// With `fold` ε < 1 (and b > 0) the warp is read at ε times the distance
// across the layers: neighbouring layers fold nearly alike, as layers folded
// together do, and the warp's slope across them is ε times smaller, so the
// layers overturn into rings (as in agate) only where ε·a·f_0 is large;
// at ε = 0 no layer ever turns back (docs/design.md, "Structure").
// With `veins` a network of thin veins runs through any of these
// (docs/design.md, "Structure"): where a second, independent fBm V (amplitude
// ratio 1/2, base frequency `vein_frequency`) is near zero, |V|/bound_V < w
// (w = `vein_width`), the value is -bound - 1 + |V|/(w bound_V),
// below every value of the structure, so colour matching puts the photo's
// darkest colours there, darkest along the zero set. The zero set of a smooth
// 3D field is a surface; a slice cuts it in curves that branch and close
// into cells, as marble's veins do, and the structure around them (its
// clouds, grain or layers) keeps its own colours.
//
// x is in voxel units, sampled at voxel centres (i + 1/2). Everything is a
// pure function of (parameters, position): a slice, a voxel or the whole cube
// comes out identical whatever order or thread computes it.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace jade {

struct NoiseParams {
    int resolution = 256;  // s, voxels along each side
    int octaves = 0;       // n; 0 = the paper's floor(log2(s))
    double k = 0.5;        // amplitude ratio, 0 < k < 1
    std::uint32_t seed = 1;
    double frequency = 1.0;  // f_0, cycles per cube side of the first octave
    double stretch = 1.0;    // r >= 1, elongation along `angle` and z
    double angle = 0.0;      // degrees counterclockwise from +x toward +y (as seen from +z)
    double bands = 0.0;      // b, layers per cube side across `angle`; 0 = plain fBm
    double warp = 0.1;       // a, how far (cube sides) the fBm displaces the layers
    bool veins = false;      // thin veins through the structure, its darkest values
    double vein_frequency = 2.0;  // cycles per cube side of the veins' first octave
    double vein_width = 0.005;    // w, the veins' half-width as a share of their fBm's range
    bool layers = false;     // with bands > 0: a 1-D fBm profile across the layers instead of the sine
    double fold = 1.0;       // ε in [0, 1], with bands > 0: how fast the warp varies across the layers
                             // relative to along them; 1 = isotropic, 0 = every layer folds alike
    // The unsharp mask build_material_volume applies to the matched levels
    // (volume/sharpen.h): β >= 0 (0 = none, the paper's volume) and the
    // Gaussian's standard deviation in voxels. Not noise, but part of how
    // the stored levels were made, so it travels with these parameters.
    double sharpen = 0.0;
    double sharpen_radius = 1.0;
    // With `exemplar` the structure is not noise: build_material_volume
    // sweeps the photo itself through the cube (volume/exemplar.h), its
    // offset wandering by up to `exemplar_wander` cube sides; the noise's
    // other parameters are then unused. Likewise part of how the levels
    // were made.
    bool exemplar = false;
    double exemplar_wander = 0.125;

    // The octave count actually used (resolves octaves == 0).
    int octave_count() const;
    // The summary lines' tail for the families beyond the fBm and the marble:
    // ", layers", ", fold E", ", veins (frequency F, width W)" and
    // ", sharpened (B over R voxels)"; empty for none.
    std::string family_suffix() const;
    // Throws jade::Error naming the parameter when one is out of range.
    void validate() const;
};

// The same structure `m` times larger: every frequency (the fBm's, the
// bands', the veins') divided by m, the warp (a length) times m, and the
// octaves shifted by log2 m (rounded) so that the finest octave stays at the
// same frequency per voxel: the detail still reaches the grid's scale. For
// a photo that spans m cube sides (Photo::span); `p` itself at m = 1.
NoiseParams magnified(const NoiseParams& p, double m);

// The gradient lattice of one seed: a permutation of 0..255, doubled so
// indices need no wrap. Built once and shared read-only by every thread.
class SimplexNoise {
public:
    explicit SimplexNoise(std::uint32_t seed);
    // Simplex noise at p; in [-1, 1] (the scale is the analytic bound of the
    // four-corner sum, not an empirical fit, so the bound is guaranteed).
    double operator()(double x, double y, double z) const;
    // Four points at once, (x[i], y[i], z[i]): each value bit for bit the
    // one above, in AVX2's four lanes where the processor has them (the
    // same operations in the same order; none fused).
    using Lanes = std::array<double, 4>;
    Lanes operator()(const Lanes& x, const Lanes& y, const Lanes& z) const;

private:
    Lanes lanes_avx2(const Lanes& x, const Lanes& y, const Lanes& z) const;
    std::uint8_t perm_[512];
    std::uint8_t gradient_[512];  // perm_[i] % 12: the gradient a hashed corner takes
};

// The fBm of Table 1 for one seed.
class Fbm {
public:
    explicit Fbm(const NoiseParams& params);
    // Sum over octaves at voxel-space position p (voxel centres are i + 1/2).
    double operator()(double x, double y, double z) const;
    // At four positions at once, each value the one above bit for bit.
    using Lanes = SimplexNoise::Lanes;
    Lanes operator()(const Lanes& x, const Lanes& y, const Lanes& z) const;
    // Frequency (cycles per voxel) and amplitude of octave i; with layers,
    // of the warp's fBm (the profile's octaves are its own).
    double frequency(int i) const;
    double amplitude(int i) const;
    int octaves() const { return octaves_; }
    // |Noise| never exceeds it: the sum of the amplitudes (1 with bands,
    // the profile's amplitudes with layers), plus 1 with veins.
    double bound() const;

private:
    double amplitude_sum(double ratio, int octaves) const;
    // The 1-D fBm across the layers at t layers (docs/design.md, "Structure").
    Lanes layer_profile(const Lanes& t) const;
    // The bound of the structure alone, without the veins.
    double structure_bound() const;
    // The veins' fBm at a voxel-space position, over its own bound: in [-1, 1].
    Lanes vein_field(const Lanes& x, const Lanes& y, const Lanes& z) const;
    SimplexNoise simplex_;
    int octaves_;
    double k_;
    double base_frequency_;        // Fr_0, cycles per voxel
    double along_x_, along_y_;     // unit direction the structure is stretched along
    double inv_stretch_;
    double bands_per_voxel_, warp_;
    double fold_ = 1.0;            // ε: the warp's coordinate across the layers is ε·w
    bool veins_;
    bool layers_;
    int profile_octaves_ = 0;       // the layers' octaves, up to the voxel grid's Nyquist frequency
    double profile_k_ = 0.5;
    // Each octave is shifted by its own seed-derived offset. Fr_i = 2^i / s puts
    // every octave's lattice points on the same voxel positions (the cube's
    // corner is a zero of every octave); the shifts decorrelate them.
    std::vector<double> offset_;
    std::vector<double> profile_offset_;  // the same for the layers' octaves
    double vein_frequency_ = 0.0;   // cycles per voxel of the veins' first octave
    double vein_width_ = 0.0;
    int vein_octaves_ = 0;
    std::vector<double> vein_offset_;     // the same for the veins' octaves
};

// Noise values of slice z = k (row-major, x fastest), s*s values.
void fbm_slice(const Fbm& fbm, int resolution, int k, float* out);

// The whole cube, x fastest then y then z; s^3 values. Parallel (TBB).
std::vector<float> fbm_volume(const NoiseParams& params);

}  // namespace jade
