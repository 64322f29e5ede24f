#include "jade/volume/histogram.h"

#include <algorithm>
#include <cmath>

namespace jade {

RgbHistogram RgbHistogram::of(const Rgb8* colours, std::size_t n) {
    RgbHistogram h;
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) ++h.counts[c][colours[i][c]];
    h.total = n;
    return h;
}

RgbHistogram RgbHistogram::of(const std::vector<Rgb8>& colours) {
    return of(colours.data(), colours.size());
}

double RgbHistogram::proportion(int channel, int level) const {
    return total ? double(counts[channel][level]) / double(total) : 0.0;
}

std::array<double, 256> RgbHistogram::cdf(int channel) const {
    std::array<double, 256> f{};
    std::size_t run = 0;
    for (int g = 0; g < 256; ++g) {
        run += counts[channel][g];
        f[g] = total ? double(run) / double(total) : 0.0;
    }
    return f;
}

double RgbHistogram::mean(int channel) const {
    double sum = 0.0;
    for (int i = 0; i < 256; ++i) sum += double(i) * double(counts[channel][i]);
    return total ? sum / double(total) : 0.0;
}

double RgbHistogram::spread(int channel) const {
    if (!total) return 0.0;
    const double m = mean(channel);
    double sum = 0.0;
    for (int i = 0; i < 256; ++i) sum += (i - m) * (i - m) * double(counts[channel][i]);
    return std::sqrt(sum / double(total));
}

int RgbHistogram::quantile(int channel, double u) const {
    const double target = std::floor(u * double(total));
    std::size_t run = 0;
    for (int g = 0; g < 256; ++g) {
        run += counts[channel][g];
        if (double(run) > target) return g;
    }
    return 255;
}

double histogram_distance(const RgbHistogram& a, const RgbHistogram& b, int channel) {
    double d = 0.0;
    for (int i = 0; i < 256; ++i) {
        const double diff = a.proportion(channel, i) - b.proportion(channel, i);
        d += diff * diff;
    }
    return d;
}

}  // namespace jade
