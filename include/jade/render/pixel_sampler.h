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

// The same for a run of one pixel's samples: what depends on the pixel
// alone (its hero start and its replicates' scrambles, a few hashes each)
// is computed once, not per sample. The values are the functions' above.
class PixelSampler {
public:
    PixelSampler(std::uint64_t seed, std::uint64_t pixel);
    int hero(std::uint64_t sample) const { return int((hero_start_ + sample) % 3); }
    FirstNumbers first_numbers(std::uint64_t sample) const;

private:
    std::uint64_t hero_start_ = 0;
    // Per replicate, the scrambles' seeds of the flight and the direction's
    // two numbers.
    std::array<std::array<std::uint32_t, 3>, kReplicates> scramble_{};
};

}  // namespace jade
