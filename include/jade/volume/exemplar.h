#pragma once
// The photo as an exemplar for the solid (docs/design.md, "The exemplar"):
// the photo's own pattern swept through the cube in depth. Slice z is the
// photo (its luma, at the cube's scale: `resolution` voxels per side)
// moved by an offset that wanders smoothly with z, so every slice the
// camera faces shows the photo's bands, veins and colour families as the
// photo has them, and the slices across them show the same pattern drawn
// out in depth: sheets, as a layered stone's layers and a marble's veins
// are, which lean and bend as the offset wanders. Colour matching (§4.2)
// then gives each slice the photo's colours by rank, as it does the noise.
//
// A parametric structure (volume/structure_estimate.h) or a synthesis from
// the photo's statistics (Heeger & Bergen 1995, tried: docs/design.md)
// reproduces what its measures see; the sweep reproduces the photo itself,
// at the price of a solid that is only as varied in depth as the wander
// makes it.

#include "jade/volume/photo.h"

#include <array>
#include <cstdint>
#include <vector>

namespace jade {

// The photo's luma at the volume's scale: its largest square of foreground
// pixels resampled to `resolution` voxels per cube side (each voxel the
// mean of the photo pixels it covers, or read bilinearly where a voxel is
// smaller than a pixel), row 0 at the top; and how it repeats beyond its
// edges: periodically where the photo tiles seamlessly (texture photos are
// often made to), mirrored where it does not, so that no seam shows.
struct Exemplar {
    int side = 0;
    std::vector<float> values;  // side², row-major
    bool periodic = false;
    // The value at integer (x, y), repeated beyond the square as above.
    float at(int x, int y) const;
};
Exemplar make_exemplar(const Photo& photo, int resolution);

// Whether a square image tiles seamlessly: the mean squared step across its
// wrapped edges (last column to first, last row to first) at most twice the
// mean squared step between neighbours inside it.
bool tiles_seamlessly(const std::vector<float>& values, int side);

// The offset (x, y), in voxels, by which slice z of an s-voxel cube reads
// the exemplar: a smooth 1-D fBm of z per axis (three octaves from one cycle
// per side, amplitude ratio 1/2) scaled to at most `wander` cube sides,
// rounded to whole voxels so that every slice is the exemplar's own pixels.
std::array<int, 2> sweep_offset(int z, int resolution, std::uint32_t seed, double wander);

// Slice z of the swept exemplar, row-major (x fastest), s² values; voxel
// (x, y) shows the exemplar's pixel at column x and row s − 1 − y (the
// slice seen from +z with y up, as the photo is seen), both moved by the
// offset.
void swept_slice(const Exemplar& exemplar, int resolution, int z, std::uint32_t seed, double wander, float* out);

}  // namespace jade
