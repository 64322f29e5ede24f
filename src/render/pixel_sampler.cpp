#include "jade/render/pixel_sampler.h"

#include "jade/core/random.h"

#include <algorithm>
#include <array>
#include <cstdint>

namespace jade {

namespace {
// A pixel's hero start comes from its stream at a sample index no sample
// takes, so it is independent of every sample's numbers.
constexpr std::uint64_t kHeroStart = ~std::uint64_t(0);

constexpr std::uint32_t reverse_bits(std::uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
}

// Owen's nested uniform scrambling of a point's 32 digits by a hash
// (Burley 2020, after Laine & Karras 2011), given the point bit-reversed.
// In the bit-reversed value each bit is flipped by a function of the seed
// and the bits below it, which are the value's bits above it, so every
// dyadic interval is permuted as a whole: a net stays a net of the same
// quality, and each step below is a bijection of the 32-bit words (x ^= x·c
// with c even leaves bit k a function of bits ≤ k), so a point is uniform
// when the seed is. The points below are made bit-reversed (the van der
// Corput point reversed is its index; Sobol's from reversed columns), which
// saves reversing them twice.
std::uint32_t owen_scramble_reversed(std::uint32_t reversed, std::uint32_t seed) {
    std::uint32_t x = reversed + seed;
    x ^= x * 0x6C50B47Cu;
    x ^= x * 0xB82F1E52u;
    x ^= x * 0xC7AFE638u;
    x ^= x * 0x8D22F6E6u;
    return reverse_bits(x);
}

// The columns of one of Sobol's generator matrices, column k as a 32-bit
// word with the first digit in the top bit, from its primitive polynomial of
// degree s (inner coefficients a_1 … a_{s-1} in the bits of `inner`, a_1
// highest) and its initial direction numbers m_1 … m_s (Bratley & Fox
// 1988's recurrence: V_k = a_1 V_{k-1} ⊕ … ⊕ a_{s-1} V_{k-s+1} ⊕ V_{k-s} ⊕
// V_{k-s} >> s), each stored bit-reversed.
using SobolColumns = std::array<std::uint32_t, 32>;
constexpr SobolColumns sobol_columns_reversed(int s, std::uint32_t inner, std::array<std::uint32_t, 2> m) {
    SobolColumns v{};
    for (int k = 0; k < 32; ++k) {
        if (k < s) {
            v[std::size_t(k)] = m[std::size_t(k)] << (31 - k);
            continue;
        }
        std::uint32_t x = v[std::size_t(k - s)] ^ (v[std::size_t(k - s)] >> s);
        for (int i = 1; i < s; ++i)
            if ((inner >> (s - 1 - i)) & 1u) x ^= v[std::size_t(k - i)];
        v[std::size_t(k)] = x;
    }
    for (auto& column : v) column = reverse_bits(column);
    return v;
}

// Sobol's second and third dimensions (Joe & Kuo 2008: x + 1 with m = 1,
// and x² + x + 1 with m = 1, 3); the first is the van der Corput sequence.
constexpr std::array<SobolColumns, 2> kSobolDirectionReversed = {sobol_columns_reversed(1, 0u, {1u, 0u}),
                                                                 sobol_columns_reversed(2, 1u, {1u, 3u})};

// Point j of a dimension, bit-reversed: the columns of j's set bits.
constexpr std::uint32_t sobol_reversed(const SobolColumns& v, std::uint32_t j) {
    std::uint32_t x = 0;
    for (std::size_t k = 0; j != 0; j >>= 1, ++k)
        if (j & 1u) x ^= v[k];
    return x;
}

// Sobol's second dimension at index j, bit-reversed, without a loop. Its
// column k holds row k of Pascal's triangle mod 2, and C(k, i) is odd
// exactly when i's bits are a subset of k's (Lucas), so digit i of the
// point is the XOR of j's bits at every k ⊇ i: the superset transform of j's
// bits over the 5-bit positions, one shift-and-mask per position bit. A
// shuffled index has bits set up to the top, where the loop's branch per
// bit, taken at random, made the film's numbers 17 % of scene A's time.
constexpr std::uint32_t sobol_second_reversed(std::uint32_t j) {
    j ^= (j >> 1) & 0x55555555u;
    j ^= (j >> 2) & 0x33333333u;
    j ^= (j >> 4) & 0x0F0F0F0Fu;
    j ^= (j >> 8) & 0x00FF00FFu;
    j ^= (j >> 16) & 0x0000FFFFu;
    return j;
}

constexpr bool second_dimension_agrees() {
    for (std::uint32_t j = 0; j < 4096; ++j)
        for (std::uint32_t high : {0u, 0x9E3779B9u, 0xFFFFF000u})
            if (sobol_second_reversed(j ^ high) != sobol_reversed(kSobolDirectionReversed[0], j ^ high)) return false;
    return true;
}
static_assert(second_dimension_agrees(), "the transform is Sobol's second dimension");

// A 32-bit point's top 24 bits as a float in [0, 1), as SampleStream::uniform's.
float to_uniform(std::uint32_t x) { return float(x >> 8) * (1.f / 16777216.f); }
}  // namespace

PixelSampler::PixelSampler(std::uint64_t seed, std::uint64_t pixel) {
    SampleStream start(seed, pixel, kHeroStart);
    hero_start_ = std::uint64_t(std::min(2, int(3.f * start.uniform())));
    // The scrambles' seeds: a hash of (seed, pixel, replicate) of its own,
    // apart from SampleStream's keys, so they are independent of every
    // sample's numbers and of the other replicates'; one per dimension.
    const std::uint64_t pixel_key = splitmix64(splitmix64(seed ^ 0x5851F42D4C957F2Dull) + pixel);
    for (int r = 0; r < kReplicates; ++r) {
        const std::uint64_t key = pixel_key ^ splitmix64(std::uint64_t(r) + 0x14057B7EF767814Full);
        for (int d = 0; d < kDimensions; ++d)
            scramble_[std::size_t(r)][std::size_t(d)] =
                std::uint32_t(splitmix64(key + std::uint64_t(d) * 0x9E3779B97F4A7C15ull) >> 32);
    }
}

FirstNumbers PixelSampler::first_numbers(std::uint64_t sample) const {
    const auto& scramble = scramble_[std::size_t(sample_replicate(sample))];
    const auto j = std::uint32_t(sample / 3 / kReplicates);
    FirstNumbers u;
    u.flight = to_uniform(owen_scramble_reversed(j, scramble[0]));
    for (std::size_t d = 0; d < 2; ++d)
        u.direction[d] =
            to_uniform(owen_scramble_reversed(sobol_reversed(kSobolDirectionReversed[d], j), scramble[d + 1]));
    return u;
}

std::array<float, 2> PixelSampler::film_numbers(std::uint64_t sample) const {
    const auto& scramble = scramble_[std::size_t(sample_replicate(sample))];
    const auto j = std::uint32_t(sample / 3 / kReplicates * 3 + sample % 3);
    // Scrambling the reversed index flips each of its bits by the bits
    // above it, and comes back in order.
    const std::uint32_t shuffled = owen_scramble_reversed(reverse_bits(j), scramble[5]);
    // The van der Corput point reversed is its index.
    return {to_uniform(owen_scramble_reversed(shuffled, scramble[3])),
            to_uniform(owen_scramble_reversed(sobol_second_reversed(shuffled), scramble[4]))};
}

int stratified_hero(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    return PixelSampler(seed, pixel).hero(sample);
}

int sample_replicate(std::uint64_t sample) { return int((sample / 3) % kReplicates); }

FirstNumbers first_numbers(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    return PixelSampler(seed, pixel).first_numbers(sample);
}

std::array<float, 2> film_numbers(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    return PixelSampler(seed, pixel).film_numbers(sample);
}

}  // namespace jade
