#include "jade/render/pixel_sampler.h"

#include "jade/core/random.h"

#include <algorithm>

namespace jade {

namespace {
// A pixel's own start comes from its stream at a sample index no sample
// takes, so it is independent of every sample's numbers.
constexpr std::uint64_t kHeroStart = ~std::uint64_t(0);
}  // namespace

int stratified_hero(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    SampleStream start(seed, pixel, kHeroStart);
    const auto first = std::uint64_t(std::min(2, int(3.f * start.uniform())));
    return int((first + sample) % 3);
}

}  // namespace jade
