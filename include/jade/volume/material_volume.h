#pragma once
// The material volume (paper §4–5.1): the colour-matched noise, stored as the
// matched 8-bit level per voxel and channel, and the optical coefficients
// derived from it.
//
//   v_c   = level / 256                          (per channel, in [0, 1))
//   v'_c  = clamp(m_c + g_c · (v_c − m_c), 0, 1) (contrast g_c about the mean level m_c)
//   σ_s   = max(0, v'_c · d_s + k_s)             (paper units)
//   σ_a   = (1 − v'_c) · d_s · d_a
//   world = paper · density_scale / cube side    (per world unit; docs/design.md, "Units")
//
// With a grey extinction (Extinction::Grey, the default) every voxel and
// channel keeps the albedo σ_s / (σ_s + σ_a) above and takes the extinction
// d_s: the stone scatters alike in every channel and its colour is its
// absorption (docs/design.md, "Coefficients"). At k_s = 0 and d_a = 1 the two
// are the same coefficients.
//
// At g_c = 1 (the default) v' = v and the formulas are the paper's §5.1. The
// contrast is the fit's second lever (docs/design.md, "Contrast"): k_s adds
// the same scattering to every voxel and so washes the structure out; g_c
// stretches the levels about their mean (as an image editor's contrast does,
// clipped to the level range), which changes the spread of the render and
// hardly its mean. g_c = 0 is the homogeneous medium of the mean level.
//
// Only the levels are stored (3 bytes a voxel): the coefficients are a
// function of a level and a few scalars, so changing k_s, the contrast, d_a
// or the scale rebuilds nothing.

#include "jade/core/bounds.h"
#include "jade/volume/color_match.h"
#include "jade/volume/noise.h"
#include "jade/volume/photo.h"
#include "jade/volume/structure_estimate.h"

#include <array>
#include <string>
#include <vector>

namespace jade {

class Progress;

// How the extinction follows from the levels: §5.1's σ_s + σ_a (Paper), or d_s
// in every voxel and channel with §5.1's albedo (Grey).
enum class Extinction { Paper, Grey };
const char* to_string(Extinction extinction);
Extinction parse_extinction(const std::string& text);

struct OpticalParams {
    Extinction extinction = Extinction::Grey;
    double ds = 1.0;                      // d_s, scattering scale
    double da = 1.0;                      // d_a, absorption scale (the paper: 0.1; README: "Defaults")
    std::array<double, 3> ks{0, 0, 0};    // k_s(R, G, B), the fitted offsets
    std::array<double, 3> contrast{1, 1, 1};   // g_c, >= 0; 1 = the paper's levels
    std::array<double, 3> mean_level{0.5, 0.5, 0.5};  // m_c in [0, 1]: the volume's mean v_c
    // Optical thickness across the object's cube for a paper coefficient of 1.
    double density_scale = 20.0;

    void validate() const;
};

struct MaterialVolume {
    int resolution = 0;          // s
    std::vector<Rgb8> levels;    // s^3, index (z * s + y) * s + x; slice z is the z-th image
    NoiseParams noise;
    StructureMode structure = StructureMode::Fbm;  // how `noise` was chosen
    MatchMode match = MatchMode::Joint;
    OpticalParams optics;
    Cube cube;
    std::string photo;           // the photo it was matched to (for the record)
    double photo_span = 1.0;     // its span (Photo::span): `noise` is in the cube's frame
    // The fit's render → display exposure (docs/design.md, "Display space"):
    // what a render of this volume is multiplied by before sRGB to look like
    // the photo. 0 = never fitted.
    double exposure = 0.0;
    // The share of voxels per channel that the build's sharpening clipped to
    // level 0 or 255 (volume/sharpen.h; 0 without it, and for a volume read
    // from a file, which does not store it).
    std::array<double, 3> sharpen_clipped{0.0, 0.0, 0.0};

    std::size_t index(int x, int y, int z) const {
        return (std::size_t(z) * resolution + y) * resolution + x;
    }
    double voxel_size() const { return cube.side / resolution; }
};

// The largest contrast the fit tries and a file may hold: at 16 nearly every
// voxel is clipped to 0 or 1 already.
constexpr double kMaxContrast = 16.0;

// v'_c of a level after the channel's contrast (above).
double contrasted_level(int level, int channel, const OpticalParams& p);
// Paper-unit coefficients for one channel's level (§5.1, with the contrast,
// and with the extinction of p.extinction).
double paper_sigma_s(int level, int channel, const OpticalParams& p);
double paper_sigma_a(int level, int channel, const OpticalParams& p);
// The mean v_c per channel over the volume's voxels (OpticalParams::mean_level).
std::array<double, 3> mean_levels(const std::vector<Rgb8>& levels);

// How many voxels hold each level, per channel.
using LevelHistograms = std::array<std::array<double, 256>, 3>;
LevelHistograms level_histograms(const std::vector<Rgb8>& levels);
// The standard deviation of channel c's contrasted levels v'_c over voxels
// counted by `histograms`, at p's contrast and mean level: g times the
// levels' own spread while no voxel clips, less as the contrast pushes
// more of them to 0 or 1.
double contrasted_spread(const LevelHistograms& histograms, int channel, const OpticalParams& p);
// d ln(contrasted_spread) / d ln g at p's contrast for channel c: 1 while
// no voxel clips, falling toward 0 as the clipped share grows.
double contrasted_spread_elasticity(const LevelHistograms& histograms, int channel, const OpticalParams& p);

// World-unit coefficients for every level and channel: a 256-entry table per
// channel, so turning levels into coefficients is a lookup.
struct CoefficientTable {
    std::array<std::array<float, 256>, 3> sigma_s{};
    std::array<std::array<float, 256>, 3> sigma_a{};

    CoefficientTable(const OpticalParams& p, double cube_side);
};

// The mean σ_s and σ_a per world unit over the volume's voxels, per channel:
// the homogeneous medium that stands for the volume where one medium must
// (the pipeline's preview.glb, io/gltf_preview.h).
struct MeanCoefficients {
    std::array<double, 3> sigma_s{0, 0, 0}, sigma_a{0, 0, 0};
};
MeanCoefficients mean_coefficients(const MaterialVolume& volume);

// Slice z of the volume as an 8-bit RGB image (row y, column x): the
// colour-matched noise image of §4.2 with the volume's contrast applied
// (level 256·v'_c), i.e. the material the renderer sees. At contrast 1 these
// are the stored levels exactly.
RgbImage8 slice_image(const MaterialVolume& volume, int z);

// Noise (§4.1), or the photo swept in depth (NoiseParams::exemplar,
// volume/exemplar.h) → colour matching (§4.2) → levels, slice by slice in
// parallel. Each slice's values are matched as soon as they exist, so no
// full float cube is held (the volume costs 3 bytes a voxel, not 7).
MaterialVolume build_material_volume(const Photo& photo, const NoiseParams& noise, MatchMode match,
                                     const OpticalParams& optics, Progress* progress = nullptr);

}  // namespace jade
