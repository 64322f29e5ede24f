#pragma once
// Pearson's χ² goodness-of-fit, for testing samplers against their densities.

#include <cmath>
#include <vector>

namespace jade_test {

// Upper critical value of χ² with k degrees of freedom at significance
// alpha = 1e-4 (Wilson–Hilferty approximation, accurate to <1% for k >= 10).
inline double chi2_critical_1e4(int k) {
    const double z = 3.719;  // one-sided normal quantile for 1e-4
    const double a = 2.0 / (9.0 * k);
    return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

// χ² statistic of observed counts against expected counts; cells whose
// expectation is below 5 are pooled, as Pearson's approximation requires.
// Returns the statistic and sets dof to (pooled cells − 1).
inline double chi2_statistic(const std::vector<double>& observed, const std::vector<double>& expected,
                             int& dof) {
    double stat = 0, pool_o = 0, pool_e = 0;
    int cells = 0;
    for (std::size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] < 5.0) {
            pool_o += observed[i];
            pool_e += expected[i];
            continue;
        }
        stat += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++cells;
    }
    if (pool_e >= 5.0) {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        ++cells;
    }
    dof = cells - 1;
    return stat;
}

}  // namespace jade_test
