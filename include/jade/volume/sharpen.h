#pragma once
// Unsharp masking of the matched levels (docs/design.md, "Sharpening"):
//
//   v' = clamp(v + β (v − G_r ∗ v), 0, 255)    per channel, G_r a 3D Gaussian of r voxels
//
// Light leaves a translucent stone about a diffusion length from where it
// entered, so a render shows the volume blurred: the finest structure (a
// marble's veins, one or two voxels wide at 256³) fades first, while the
// coarse clouds keep their contrast and, with it, the spread the fit matches.
// The mask raises each spatial frequency f (cycles per voxel) of the levels
// by 1 + β (1 − Ĝ(f)), Ĝ(f) ≈ exp(−2π² r² f²), and leaves the mean and
// the coarse structure as they were: the fine structure is made stronger in
// the volume so that more of it survives the transport. β = 0 is the
// paper's volume.

#include "jade/core/image.h"
#include "jade/volume/noise.h"

#include <array>
#include <string>
#include <vector>

namespace jade {

// Sharpens `levels` (s³ voxels, index (z·s + y)·s + x) in place by β =
// `amount` with a Gaussian of standard deviation `radius` voxels (cut at
// three of them; the edges repeat their last voxel). Returns per channel
// the share of voxels the result clipped to level 0 or 255. Deterministic
// whatever the thread count. Holds one float per voxel while it runs (4
// bytes beside the levels' 3, against the 44 more the .vdb's write
// takes, io/vdb_io.h).
std::array<double, 3> sharpen_levels(std::vector<Rgb8>& levels, int resolution, double amount, double radius);

// Above this share of clipped voxels in a channel the sharpening flattens
// what it meant to raise: a clipped vein or layer loses its own levels
// (Onyx010's layers at β = 4 clip 6–9 %, and the fit of that volume ran to
// its largest contrast; at β = 2 under 5 %; docs/design.md, "Sharpening").
constexpr double kSharpenClipWarning = 0.05;

// The sharpening a fit chooses where it raised the density scale to its
// ceiling (fit/fit_session.h, sharpening_for), and the one `jaderender
// volume`, which fits nothing, takes for --sharpen auto (the library's
// NoiseParams keep 0, the paper's levels). At the default radius, on the
// onyx photos (docs/design.md, "Sharpening"): at 0.5 the fits converged and
// the renders' structure came nearer the photo's, the whole render's D
// about as it was; at 1 the demo's fit ran its blue contrast to the largest
// there is, and at 4 both onyx fits tried ran out of renders.
constexpr double kDefaultSharpen = 0.5;

// The sharpening a fit chooses where it raised the density scale short of
// its ceiling (sharpening_for): the most measured to converge there.
// Onyx010's stone sharpened by it rendered with a structure distance of
// 0.370 on the cow against 0.432 at kDefaultSharpen, on the vase 0.517
// against 0.583 (docs/design.md, "Sharpening").
constexpr double kSharperStone = 1.0;

// The noise options `jaderender volume` builds a volume from a photo with:
// the paper's fBm (NoiseParams' own) sharpened by kDefaultSharpen.
NoiseParams default_photo_noise();

// The warning for a sharpening that clipped more than kSharpenClipWarning
// of a channel's voxels, naming the shares and --sharpen; empty otherwise.
std::string sharpening_warning(double amount, const std::array<double, 3>& clipped);

}  // namespace jade
