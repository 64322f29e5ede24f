#include "jade/volume/color_match.h"

#include "jade/core/error.h"
#include "jade/volume/histogram.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace jade {

const char* to_string(MatchMode mode) {
    return mode == MatchMode::PerChannel ? "per-channel" : "joint";
}

MatchMode parse_match_mode(const std::string& text) {
    if (text == "per-channel") return MatchMode::PerChannel;
    if (text == "joint") return MatchMode::Joint;
    throw Error("--match must be 'per-channel' or 'joint', got '" + text + "'");
}

namespace {

using Vec3 = std::array<double, 3>;

// Principal axes of the colour cloud, by power iteration on the covariance
// (3x3, symmetric): the first axis and a second one orthogonal to it. The first
// axis is oriented toward brighter colours, so high noise means bright stone in
// both matching modes.
std::array<Vec3, 2> principal_axes(const std::vector<std::pair<std::uint32_t, std::size_t>>& colours,
                                   std::size_t total) {
    Vec3 mean{0, 0, 0};
    for (const auto& [packed, count] : colours)
        for (int c = 0; c < 3; ++c) mean[c] += double((packed >> (8 * (2 - c))) & 255) * count;
    for (double& m : mean) m /= double(total);
    double cov[3][3] = {};
    for (const auto& [packed, count] : colours) {
        Vec3 d;
        for (int c = 0; c < 3; ++c) d[c] = double((packed >> (8 * (2 - c))) & 255) - mean[c];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) cov[a][b] += d[a] * d[b] * double(count);
    }
    auto power = [&](Vec3 v, const Vec3* deflate) {
        for (int it = 0; it < 200; ++it) {
            Vec3 w{0, 0, 0};
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) w[a] += cov[a][b] * v[b];
            if (deflate) {  // stay orthogonal to the first axis
                const double p = w[0] * (*deflate)[0] + w[1] * (*deflate)[1] + w[2] * (*deflate)[2];
                for (int c = 0; c < 3; ++c) w[c] -= p * (*deflate)[c];
            }
            const double len = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            if (len < 1e-12) return v;  // degenerate cloud: keep the start axis
            for (int c = 0; c < 3; ++c) w[c] /= len;
            v = w;
        }
        return v;
    };
    const double r3 = 1.0 / std::sqrt(3.0);
    Vec3 first = power({r3, r3, r3}, nullptr);
    if (first[0] + first[1] + first[2] < 0)
        for (double& x : first) x = -x;
    // A start vector orthogonal to the first axis for the second.
    Vec3 start = std::abs(first[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const double p = start[0] * first[0] + start[1] * first[1] + start[2] * first[2];
    for (int c = 0; c < 3; ++c) start[c] -= p * first[c];
    const double len = std::sqrt(start[0] * start[0] + start[1] * start[1] + start[2] * start[2]);
    for (double& x : start) x /= len;
    return {first, power(start, &first)};
}

std::vector<Rgb8> joint_table(const std::vector<Rgb8>& photo, std::size_t m) {
    // Distinct colours with their pixel counts (a photo has far fewer distinct
    // colours than pixels).
    std::vector<std::uint32_t> packed(photo.size());
    for (std::size_t i = 0; i < photo.size(); ++i)
        packed[i] = (std::uint32_t(photo[i][0]) << 16) | (std::uint32_t(photo[i][1]) << 8) | photo[i][2];
    std::sort(packed.begin(), packed.end());
    std::vector<std::pair<std::uint32_t, std::size_t>> colours;
    for (std::uint32_t p : packed) {
        if (colours.empty() || colours.back().first != p) colours.push_back({p, 0});
        ++colours.back().second;
    }
    const auto axes = principal_axes(colours, photo.size());
    auto key = [&](std::uint32_t p, int axis) {
        double k = 0;
        for (int c = 0; c < 3; ++c) k += axes[axis][c] * double((p >> (8 * (2 - c))) & 255);
        return k;
    };
    // Order along the first axis; ties (colours at the same position on it)
    // along the second, then by value, so the order is total and deterministic.
    std::sort(colours.begin(), colours.end(), [&](const auto& a, const auto& b) {
        const double ka = key(a.first, 0), kb = key(b.first, 0);
        if (ka != kb) return ka < kb;
        const double la = key(a.first, 1), lb = key(b.first, 1);
        if (la != lb) return la < lb;
        return a.first < b.first;
    });
    std::vector<std::size_t> cumulative(colours.size());
    std::size_t run = 0;
    for (std::size_t i = 0; i < colours.size(); ++i) cumulative[i] = run += colours[i].second;

    std::vector<Rgb8> table(m);
    for (std::size_t r = 0; r < m; ++r) {
        // The pixel at position floor((r + 1/2) / m * N) of the sorted photo.
        const std::size_t pos =
            std::size_t(std::floor((double(r) + 0.5) / double(m) * double(photo.size())));
        const std::size_t idx =
            std::size_t(std::upper_bound(cumulative.begin(), cumulative.end(), pos) - cumulative.begin());
        const std::uint32_t p = colours[std::min(idx, colours.size() - 1)].first;
        table[r] = {std::uint8_t(p >> 16), std::uint8_t(p >> 8), std::uint8_t(p)};
    }
    return table;
}

std::vector<Rgb8> per_channel_table(const std::vector<Rgb8>& photo, std::size_t m) {
    const RgbHistogram h = RgbHistogram::of(photo);
    std::vector<Rgb8> table(m);
    for (int c = 0; c < 3; ++c) {
        // Walk the rank positions and the CDF together: both increase.
        std::size_t run = h.counts[c][0];
        int g = 0;
        for (std::size_t r = 0; r < m; ++r) {
            const double pos = std::floor((double(r) + 0.5) / double(m) * double(photo.size()));
            while (double(run) <= pos && g < 255) run += h.counts[c][++g];
            table[r][c] = std::uint8_t(g);
        }
    }
    return table;
}

// Order-preserving map of a float to an unsigned integer (IEEE 754 trick):
// flip all bits of negatives, the sign bit of positives.
inline std::uint32_t float_key(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

}  // namespace

std::vector<Rgb8> rank_colour_table(const std::vector<Rgb8>& photo_foreground, std::size_t m,
                                    MatchMode mode) {
    if (photo_foreground.empty()) throw Error("colour matching needs at least one foreground pixel");
    if (m == 0) return {};
    return mode == MatchMode::PerChannel ? per_channel_table(photo_foreground, m)
                                         : joint_table(photo_foreground, m);
}

void match_slice(const float* noise, std::size_t n, const std::vector<Rgb8>& table, Rgb8* out) {
    if (table.size() != n) throw Error("internal: rank table size differs from the slice size");
    // Sort (value, position) pairs packed in one 64-bit key: value first,
    // position breaks ties.
    std::vector<std::uint64_t> keys(n);
    for (std::size_t v = 0; v < n; ++v) keys[v] = (std::uint64_t(float_key(noise[v])) << 32) | v;
    std::sort(keys.begin(), keys.end());
    for (std::size_t r = 0; r < n; ++r) out[keys[r] & 0xFFFFFFFFu] = table[r];
}

}  // namespace jade
