#pragma once
// Colour matching of noise slices to the photo (paper §4.2).
//
// Each slice is matched by rank: the voxel whose noise value has rank r among
// the slice's M voxels takes the photo colour at quantile (r + 1/2) / M. This
// is the paper's M(G) = F_photo^-1(F_noise(G)) evaluated on the unquantised
// noise, so the matched slice's histogram equals the photo's to within one
// pixel count (a noise quantised to 256 levels first would tie thousands of
// voxels and could not reach the photo's histogram).
//
// Two ways to choose "the photo colour at quantile u":
//  - PerChannel, the paper's: each channel independently, (Q_R(u), Q_G(u),
//    Q_B(u)). Every channel's histogram is matched exactly, but the colour
//    triples are invented: a photo of red and grey stone yields a ramp of
//    colours neither stone has, and a minority colour can vanish (Fig. 11c).
//  - Joint: the photo's foreground pixels sorted along their principal colour
//    axis (the direction of largest colour variance), u picks a real pixel.
//    Every voxel gets a colour the photo has, in the photo's proportions.

#include "jade/volume/photo.h"

#include <string>
#include <vector>

namespace jade {

enum class MatchMode { PerChannel, Joint };

const char* to_string(MatchMode mode);
// Parses "per-channel" or "joint"; throws jade::Error otherwise.
MatchMode parse_match_mode(const std::string& text);

// The colour for each rank of an M-voxel slice: table[r] is the photo colour
// at quantile (r + 1/2) / M. Every slice has M voxels, so one table serves all.
std::vector<Rgb8> rank_colour_table(const std::vector<Rgb8>& photo_foreground, std::size_t m,
                                    MatchMode mode);

// out[v] = table[rank of noise[v] within the slice]; ties in value are ranked
// by position, so the result is deterministic. n == table.size().
void match_slice(const float* noise, std::size_t n, const std::vector<Rgb8>& table, Rgb8* out);

}  // namespace jade
