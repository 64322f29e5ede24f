#pragma once
// Small counter-based random numbers: SplitMix64 (Steele, Lea & Flood 2014).
// A value is a pure function of (seed, counter), so any thread may draw any
// number and results never depend on scheduling.

#include <cstdint>

namespace jade {

constexpr std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// Uniform double in [0, 1) from 53 random bits.
constexpr double to_unit_double(std::uint64_t bits) {
    return double(bits >> 11) * (1.0 / 9007199254740992.0);
}

// A sequential stream over splitmix64, for set-up work such as shuffles.
class SplitMix64 {
public:
    explicit constexpr SplitMix64(std::uint64_t seed) : state_(seed) {}
    constexpr std::uint64_t next() { return splitmix64(state_++ * 0x9E3779B97F4A7C15ull + 1); }
    constexpr double uniform() { return to_unit_double(next()); }
    // Uniform integer in [0, n), n > 0 (Lemire's multiply-shift; bias < n / 2^64).
    std::uint64_t below(std::uint64_t n) {
        return std::uint64_t((unsigned __int128)next() * n >> 64);
    }

private:
    std::uint64_t state_;
};

}  // namespace jade

namespace jade {

// The random numbers of one camera sample: a stream keyed by (seed, pixel,
// sample index), so a pixel's value never depends on which thread rendered it
// or in which order (renders are bit-identical whatever the thread count).
class SampleStream {
public:
    // A placeholder to assign a keyed stream to (arrays of streams).
    SampleStream() = default;
    SampleStream(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample)
        : key_(splitmix64(splitmix64(seed ^ 0xA0761D6478BD642Full) + pixel) ^
               splitmix64(sample * 0xE7037ED1A0B428DBull + 0x8EBC6AF09C88C6E3ull)) {}
    // Uniform float in [0, 1): 24 random bits, so 1 is never returned.
    float uniform() {
        return float(splitmix64(key_ + 0x9E3779B97F4A7C15ull * ++counter_) >> 40) *
               (1.f / 16777216.f);
    }

private:
    std::uint64_t key_ = 0;
    std::uint64_t counter_ = 0;
};

}  // namespace jade
