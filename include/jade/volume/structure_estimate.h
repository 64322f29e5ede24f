#pragma once
// A noise structure estimated from the photo (docs/design.md, "Structure"):
// the fBm's base frequency, amplitude ratio, stretch and angle chosen so that
// a slice of the volume has the photo's spectrum, at the photo's scale and in
// its direction. Analysis by synthesis: candidate slices are generated,
// histogram-matched to the photo's luma as the volume's slices will be, and
// compared with the photo by their spectra (texture_spectrum.h).

#include "jade/volume/noise.h"
#include "jade/volume/photo.h"
#include "jade/volume/texture_spectrum.h"

#include <string>

namespace jade {

// How the volume's structure is chosen: the paper's fixed fBm (§4.1), a
// noise estimated from the photo, or the photo itself swept through the
// cube as an exemplar (volume/exemplar.h).
enum class StructureMode { Fbm, Photo, Exemplar };
StructureMode parse_structure_mode(const std::string& s);  // "fbm" | "photo" | "exemplar"; throws jade::Error
// The names parse_structure_mode takes, as an error message lists them.
const char* structure_mode_names();
const char* to_string(StructureMode m);

// The photo's luma as a texture (its foreground as the mask); how many of its
// pixels the foreground's bounding box spans along its larger side (the
// photo's own frame, in which the estimate below works); and how many span
// the cube side: that over the photo's span (Photo::span; a slab photo at
// span 1 spans the side it shows).
GrayImage photo_luma(const Photo& photo);
double photo_extent_pixels(const Photo& photo);
double photo_pixels_per_side(const Photo& photo);

// Slice z of the noise, as seen from +z (row 0 at the top, the largest y),
// with its values replaced by the photo's luma of the same rank: what a slice
// of the colour-matched volume shows.
GrayImage matched_noise_slice(const NoiseParams& noise, int z, const std::vector<float>& sorted_luma);

// The mean structure distance between slices of this noise, matched to the
// photo, and the photo; and the mean orientation strength, coherence and
// orientation defects (texture_spectrum.h) of those slices.
struct StructureFit {
    NoiseParams noise;
    double distance = 0.0;
    double strength = 0.0;
    double orientation = 0.0;
    double coherence = 0.0;
    double defects = 0.0;
};
StructureFit evaluate_structure(const NoiseParams& noise, const Photo& photo);

// The same measures of a built volume's own slices (levels as stored,
// s³, index (z·s + y)·s + x; their luma), a quarter and three quarters
// deep, against the photo at the cube's scale: what the written levels
// show, sharpened or swept from the photo (volume/exemplar.h), which the
// noise's parameters alone do not say. The result's `noise` is left default.
StructureFit measure_slice_structure(const std::vector<Rgb8>& levels, int resolution, const Photo& photo);
// The same measures of the slices across those, which no camera facing the
// cube squarely sees face on but a vase's shoulders, a side view or a
// Blender render from elsewhere do: normal to x and normal to y, each a
// quarter and three quarters deep, averaged (its orientation is left 0: it
// has no one frame). A structure made for the view along z (the sweep,
// volume/exemplar.h) can be far from the photo here.
StructureFit measure_slice_structure_across(const std::vector<Rgb8>& levels, int resolution, const Photo& photo);

// The noise of a StructureFit is in the cube's frame (cycles per cube side);
// its measures compare slices at the photo's own scale, the noise magnified
// down by the photo's span (magnified in noise.h), with the photo.
struct StructureEstimate {
    StructureFit chosen;   // the estimated parameters
    StructureFit paper;    // the paper's fBm (f_0 = 1, r = 1, no bands, same k and seed), for comparison
    TextureSpectrum photo;
    double photo_span = 1.0;  // the photo's span, by which the outcome was magnified (Photo::span)
    double seconds = 0.0;
    int evaluations = 0;   // candidate structures evaluated (two matched slices each), repeats not counted
};
// Searches f_0, k, r, the bands b and their warp a (coordinate descent over fixed grids, from the
// paper's fBm, a marble and folded layers, NoiseParams::layers) with the angle taken from the
// photo's orientation, then the bands' fold and warp together over their whole grid, in the
// photo's frame, and magnifies the outcome by the photo's span. `base`
// gives the resolution, octaves and seed, and whether the structure has veins
// (NoiseParams::veins; then their frequency and width are searched too).
StructureEstimate estimate_structure(const Photo& photo, const NoiseParams& base);

// The noise a volume is built with: `given` itself for the paper's fBm,
// `given` with NoiseParams::exemplar set for the photo as the exemplar, or
// its resolution, octaves and seed with the structure estimated from the
// photo. The estimate (when made) is left in `estimate`.
NoiseParams choose_noise(const Photo& photo, const NoiseParams& given, StructureMode mode,
                         StructureEstimate* estimate = nullptr);

}  // namespace jade
