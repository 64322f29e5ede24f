#pragma once
// The dimensions a pixel's samples share out between them (stratified
// sampling), where the rest of a sample's numbers are its own stream's
// (core/random.h). Each sample's value in such a dimension is uniform on its
// own, so every sample stays an unbiased estimate; across a pixel's samples
// the values cover the dimension evenly, so the spread between them leaves
// the pixel's mean (docs/design.md, "Stratified pixel samples"). A value
// depends only on (seed, pixel, sample index): a render split into passes
// or pieces draws the same ones.

#include <cstdint>

namespace jade {

// The hero channel of sample `sample` of pixel `pixel` (render/integrator.h):
// the samples take the three channels in turn from a start drawn per pixel,
// so every three consecutive samples have one of each. The spread between
// the heroes' estimates is a large part of a chromatic medium's noise.
int stratified_hero(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample);

}  // namespace jade
