#pragma once
// The dimensions a pixel's samples share out between them, where the rest of
// a sample's numbers are its own stream's (core/random.h). Each sample's value
// in such a dimension is uniform on its own, so every sample stays an
// unbiased estimate; across a pixel's samples the values cover the dimension
// evenly, so much of the spread between them leaves the pixel's mean
// (docs/design.md, "Stratified pixel samples"). A value depends only on
// (seed, pixel, sample index): a render split into passes or pieces draws
// the same ones.

#include <array>
#include <cstdint>

namespace jade {

// The hero channel of sample `sample` of pixel `pixel` (render/integrator.h):
// the samples take the three channels in turn from a start drawn per pixel,
// so every three consecutive samples have one of each. The spread between
// the heroes' estimates is a large part of a chromatic medium's noise.
int stratified_hero(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample);

// A pixel's samples in kReplicates independent replicates: the three samples
// of one turn of the heroes (samples 3t, 3t + 1, 3t + 2) belong to replicate
// t mod kReplicates, so every replicate holds whole turns. Each replicate
// draws its first numbers (below) from its own randomised
// low-discrepancy sequence; the replicates' means are independent and
// identically distributed, so the spread between them measures the error of
// the pixel's mean, which the spread between its samples, no longer
// independent within a replicate, overstates (randomised quasi-Monte Carlo;
// render/film.h).
constexpr int kReplicates = 4;
int sample_replicate(std::uint64_t sample);

// The numbers a camera path's first steps take from the pixel: the number
// of its first free flight drawn whole (a homogeneous medium's, or one whose
// extinction is the same everywhere; render/integrator.h) and the two of its
// first scattering's direction. Replicate r's turn t takes point ⌊t /
// kReplicates⌋ of Sobol's first three dimensions (the van der Corput
// sequence, then Joe & Kuo's direction numbers), each with Owen's nested
// uniform scrambling seeded per (pixel, replicate, dimension). A point is
// then uniform in the unit cube, so every sample stays unbiased, and the
// replicates are independent; a replicate's first 2^k points are a (0, k,
// 2)-net in the flight and the direction's first number and a (1, k, 2)-net
// in the other two pairs: the first flights and directions cover their
// distributions evenly. The three heroes of a turn share a point. Each
// number is a multiple of 2^-24 below 1, as SampleStream::uniform's.
struct FirstNumbers {
    float flight = 0.f;
    std::array<float, 2> direction{};
};
FirstNumbers first_numbers(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample);

// The film position of sample `sample` within its pixel, (x, y) in [0, 1)²
// from the pixel's corner. Replicate r's samples take, in their order
// (point 3t + k for the k-th sample of its t-th turn), the points of
// Sobol's first two dimensions at an index shuffled by a nested uniform
// scramble of its own (Burley 2020's padding: each bit of the index
// flipped by a hash of the bits above it), each dimension with Owen's
// scrambling seeded per (pixel, replicate). The shuffle maps every aligned
// block of 2^k indices onto one, and an aligned block of a (0, 2)-sequence
// is a (0, k, 2)-net: a replicate's first 2^k positions hold one in every
// elementary interval of area 2^-k of the pixel, so an edge across it (a
// silhouette, the rim of the light's reflection) is covered in proportion,
// not by chance. Each position is uniform on its own and independent of
// the first numbers above and between replicates (every dimension has a
// scramble of its own); the shuffle keeps the positions' order from
// following the first numbers' across a replicate.
std::array<float, 2> film_numbers(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample);

// The same for a run of one pixel's samples: what depends on the pixel
// alone (its hero start and its replicates' scrambles, a few hashes each)
// is computed once, not per sample. The values are the functions' above.
class PixelSampler {
public:
    PixelSampler(std::uint64_t seed, std::uint64_t pixel);
    int hero(std::uint64_t sample) const { return int((hero_start_ + sample) % 3); }
    FirstNumbers first_numbers(std::uint64_t sample) const;
    std::array<float, 2> film_numbers(std::uint64_t sample) const;

private:
    std::uint64_t hero_start_ = 0;
    // Per replicate, the scrambles' seeds of the flight, the direction's two
    // numbers, the film position's two and the film's index shuffle.
    static constexpr int kDimensions = 6;
    std::array<std::array<std::uint32_t, kDimensions>, kReplicates> scramble_{};
};

}  // namespace jade
