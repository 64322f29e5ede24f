#include "jade/fit/broyden.h"

#include <algorithm>
#include <cmath>

namespace jade {

namespace {
// The most a diagonal changes in one update, as a factor.
constexpr double kMaxDiagonalChange = 4.0;
// The least det(J) as a share of the diagonals' product.
constexpr double kMinDetShare = 0.25;
}  // namespace

std::array<double, 2> BroydenJacobian2::newton_step(const std::array<double, 2>& f) const {
    const double d = det();
    return {(-f[0] * m[1][1] + f[1] * m[0][1]) / d, (-f[1] * m[0][0] + f[0] * m[1][0]) / d};
}

bool BroydenJacobian2::update(const std::array<double, 2>& dx, const std::array<double, 2>& df,
                              const std::array<double, 2>& min_change) {
    const std::array<double, 2> w{m[0][0] * m[0][0], m[1][1] * m[1][1]};
    const double norm2 = w[0] * dx[0] * dx[0] + w[1] * dx[1] * dx[1];
    if (!(norm2 > 0.0)) return false;
    bool changed = false;
    for (int i = 0; i < 2; ++i) {
        const double expected = m[i][0] * dx[0] + m[i][1] * dx[1];
        if (!(std::max(std::abs(expected), std::abs(df[i])) >= min_change[std::size_t(i)])) continue;
        changed = true;
        const double miss = df[i] - expected;
        const double old = m[i][i];
        for (int j = 0; j < 2; ++j) m[i][j] += miss * w[j] * dx[j] / norm2;
        m[i][i] = std::clamp(m[i][i], old / kMaxDiagonalChange, old * kMaxDiagonalChange);
    }
    const double cross = m[0][1] * m[1][0];
    const double allowed = (1.0 - kMinDetShare) * m[0][0] * m[1][1];
    if (cross > allowed) {
        const double shrink = std::sqrt(allowed / cross);
        m[0][1] *= shrink;
        m[1][0] *= shrink;
    }
    return changed;
}

}  // namespace jade
