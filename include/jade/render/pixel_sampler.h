#pragma once
// The dimensions a pixel's samples share out between them, where the rest of
// a sample's numbers are its own stream's (core/random.h). Each sample's value
// in such a dimension is uniform on its own, so every sample stays an
// unbiased estimate; across a pixel's samples the values cover the dimension
// evenly, so much of the spread between them leaves the pixel's mean
// (docs/design.md, "Stratified pixel samples"). A value depends only on
// (seed, pixel, sample index): a render split into passes or pieces draws
// the same ones.

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
// draws its first-flight numbers (below) from its own randomised
// low-discrepancy sequence; the replicates' means are independent and
// identically distributed, so the spread between them measures the error of
// the pixel's mean, which the spread between its samples, no longer
// independent within a replicate, overstates (randomised quasi-Monte Carlo;
// render/film.h).
constexpr int kReplicates = 4;
int sample_replicate(std::uint64_t sample);

// The number of a camera path's first free flight drawn whole (a homogeneous
// medium's, or one whose extinction is the same everywhere; render/integrator.h):
// point ⌊t / kReplicates⌋ of the van der Corput sequence, with Owen's nested
// uniform scrambling seeded per (pixel, replicate). Each number is then
// uniform on its own and the replicates are independent, while a
// replicate's first 2^k numbers keep one in each interval of width 2^-k: the
// first flight's lengths cover their distribution evenly. The three heroes
// of a turn share a number. A multiple of 2^-24 below 1, as
// SampleStream::uniform's. (The first scattering direction drawn the same
// way is not taken yet: docs/design.md, "Stratified pixel samples".)
float first_flight_number(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample);

}  // namespace jade
