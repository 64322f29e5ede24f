#pragma once
// Per-channel histograms of 8-bit levels (paper §4.2 and Table 3). The same
// histograms drive colour matching, the fitter's brightness A(κ) and its
// difference D(κ), and the comparison picture.

#include "jade/volume/photo.h"

#include <array>
#include <cstddef>
#include <vector>

namespace jade {

struct RgbHistogram {
    // counts[c][i]: pixels whose channel c has level i.
    std::array<std::array<std::size_t, 256>, 3> counts{};
    std::size_t total = 0;

    static RgbHistogram of(const std::vector<Rgb8>& colours);
    static RgbHistogram of(const Rgb8* colours, std::size_t n);

    // H(i, κ): the proportion of pixels at level i.
    double proportion(int channel, int level) const;
    // F(g) = proportion at levels <= g.
    std::array<double, 256> cdf(int channel) const;
    // A(κ) = sum_i i * H(i, κ), in gray levels 0..255.
    double mean(int channel) const;
    // S(κ): the standard deviation of the levels, in gray levels.
    double spread(int channel) const;
    // The level at quantile u in [0, 1): the smallest g with count(<= g) > u * total.
    int quantile(int channel, double u) const;
};

// D(κ) = sum_i (H_a(i, κ) - H_b(i, κ))^2.
double histogram_distance(const RgbHistogram& a, const RgbHistogram& b, int channel);

}  // namespace jade
