#include "jade/render/pixel_sampler.h"

#include "jade/core/random.h"

#include <algorithm>
#include <cstdint>

namespace jade {

namespace {
// A pixel's hero start comes from its stream at a sample index no sample
// takes, so it is independent of every sample's numbers.
constexpr std::uint64_t kHeroStart = ~std::uint64_t(0);

std::uint32_t reverse_bits(std::uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
}

// Point j of the van der Corput sequence (the radical inverse of j in base
// 2, as 32 bits) with Owen's nested uniform scrambling by a hash (Burley
// 2020, after Laine & Karras 2011). In the bit-reversed value each bit is
// flipped by a function of the seed and the bits below it, which are the
// value's bits above it, so every dyadic interval is permuted as a whole:
// the first 2^k points keep one point in each interval of width 2^-k, and
// each step below is a bijection of the 32-bit words (x ^= x·c with c even
// leaves bit k a function of bits ≤ k), so a point is uniform when the seed is.
std::uint32_t scrambled_van_der_corput(std::uint32_t j, std::uint32_t seed) {
    std::uint32_t x = j;  // reverse_bits(radical inverse of j) is j itself
    x += seed;
    x ^= x * 0x6C50B47Cu;
    x ^= x * 0xB82F1E52u;
    x ^= x * 0xC7AFE638u;
    x ^= x * 0x8D22F6E6u;
    return reverse_bits(x);
}
}  // namespace

int stratified_hero(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    SampleStream start(seed, pixel, kHeroStart);
    const auto first = std::uint64_t(std::min(2, int(3.f * start.uniform())));
    return int((first + sample) % 3);
}

int sample_replicate(std::uint64_t sample) { return int((sample / 3) % kReplicates); }

float first_flight_number(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    // The scramble's seed: a hash of (seed, pixel, replicate) of its own,
    // apart from SampleStream's keys, so it is independent of every
    // sample's numbers and of the other replicates' seeds.
    const std::uint64_t key = splitmix64(splitmix64(seed ^ 0x5851F42D4C957F2Dull) + pixel) ^
                              splitmix64(std::uint64_t(sample_replicate(sample)) + 0x14057B7EF767814Full);
    const auto j = std::uint32_t(sample / 3 / kReplicates);
    // The top 24 bits, as SampleStream::uniform's numbers.
    return float(scrambled_van_der_corput(j, std::uint32_t(splitmix64(key) >> 32)) >> 8) * (1.f / 16777216.f);
}

}  // namespace jade
