#include "jade/core/simplex_least_squares.h"

#include "jade/core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace jade {

void project_to_simplex(std::vector<double>& v) {
    // The projection is max(v − τ, 0) with τ set so that the result sums to
    // 1: τ is found from v sorted in decreasing order.
    std::vector<double> u = v;
    std::sort(u.begin(), u.end(), std::greater<double>());
    double run = 0.0, tau = 0.0;
    for (std::size_t k = 0; k < u.size(); ++k) {
        run += u[k];
        const double t = (run - 1.0) / double(k + 1);
        if (u[k] - t > 0.0) tau = t;
    }
    for (double& x : v) x = std::max(x - tau, 0.0);
}

void project_to_simplex(std::vector<double>& v, const MixtureMean& mean) {
    if (mean.column_means.empty()) return project_to_simplex(v);
    const std::vector<double>& m = mean.column_means;
    // KKT: p = max(v − τ − μ·m, 0); for each μ, τ is the simplex
    // projection's, and the mean of p falls as μ grows.
    auto at = [&](double mu) {
        std::vector<double> p(v.size());
        for (std::size_t j = 0; j < v.size(); ++j) p[j] = v[j] - mu * m[j];
        project_to_simplex(p);
        return p;
    };
    auto excess = [&](const std::vector<double>& p) {
        return std::inner_product(p.begin(), p.end(), m.begin(), 0.0) - mean.mean;
    };
    // The excess is piecewise linear and falling in μ: bracket a root, then
    // regula falsi with the Illinois halving (a few evaluations, each a
    // sort), to a mean within 10⁻⁹ of the scale of the column means.
    const double tolerance = 1e-9 * std::max(1.0, std::abs(mean.mean));
    double lo = -1.0, hi = 1.0;
    double e_lo = excess(at(lo)), e_hi = excess(at(hi));
    for (int i = 0; i < 200 && e_lo < 0.0; ++i) e_lo = excess(at(lo *= 2.0));
    for (int i = 0; i < 200 && e_hi > 0.0; ++i) e_hi = excess(at(hi *= 2.0));
    std::vector<double> p = at(lo);
    if (std::abs(e_lo) > tolerance) p = at(hi);
    int side = 0;
    for (int i = 0; i < 200 && std::abs(excess(p)) > tolerance && hi - lo > 1e-15 * std::max(std::abs(lo), std::abs(hi));
         ++i) {
        const double mu = e_lo == e_hi ? 0.5 * (lo + hi) : (lo * e_hi - hi * e_lo) / (e_hi - e_lo);
        p = at(std::clamp(mu, lo, hi));
        const double e = excess(p);
        if (e > 0.0) {
            lo = mu, e_lo = e;
            if (side == 1) e_hi *= 0.5;
            side = 1;
        } else {
            hi = mu, e_hi = e;
            if (side == -1) e_lo *= 0.5;
            side = -1;
        }
    }
    v = p;
}

namespace {

struct Problem {
    const std::vector<std::vector<double>>& k;
    const std::vector<double>& h;
    const MixtureMean& mean;

    // r = K·p − h
    std::vector<double> residual(const std::vector<double>& p) const {
        std::vector<double> r(h.size());
        for (std::size_t i = 0; i < h.size(); ++i) r[i] = -h[i];
        for (std::size_t j = 0; j < k.size(); ++j) {
            if (p[j] == 0.0) continue;
            for (std::size_t i = 0; i < h.size(); ++i) r[i] += p[j] * k[j][i];
        }
        return r;
    }
    // ∇f = 2·Kᵀ·r
    std::vector<double> gradient(const std::vector<double>& r) const {
        std::vector<double> g(k.size());
        for (std::size_t j = 0; j < k.size(); ++j)
            g[j] = 2.0 * std::inner_product(k[j].begin(), k[j].end(), r.begin(), 0.0);
        return g;
    }
    static double value(const std::vector<double>& r) { return std::inner_product(r.begin(), r.end(), r.begin(), 0.0); }

    // The largest eigenvalue of KᵀK by power iteration: ∇f is Lipschitz
    // with 2·λ_max, the step is its inverse. Raised by a tenth, since the
    // iteration approaches λ_max from below (and halved again by the
    // solver where a plain step still raises f).
    double lipschitz() const {
        std::vector<double> x(k.size(), 1.0 / std::sqrt(double(k.size()))), y(h.size());
        double lambda = 0.0;
        for (int it = 0; it < 50; ++it) {
            std::fill(y.begin(), y.end(), 0.0);
            for (std::size_t j = 0; j < k.size(); ++j)
                for (std::size_t i = 0; i < h.size(); ++i) y[i] += x[j] * k[j][i];
            double norm = 0.0;
            for (std::size_t j = 0; j < k.size(); ++j) {
                x[j] = std::inner_product(k[j].begin(), k[j].end(), y.begin(), 0.0);
                norm += x[j] * x[j];
            }
            norm = std::sqrt(norm);
            if (!(norm > 0.0)) return 1.0;
            lambda = norm;
            for (double& v : x) v /= norm;
        }
        return 2.0 * 1.1 * lambda;
    }

    // min over the feasible set of g·s: a vertex of the simplex, or with
    // the mean, a vertex of its slice: one column at the mean, or two on
    // either side of it mixed to the mean.
    double least_linear(const std::vector<double>& g) const {
        if (mean.column_means.empty()) return *std::min_element(g.begin(), g.end());
        const std::vector<double>& m = mean.column_means;
        double least = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < m.size(); ++i) {
            const double di = m[i] - mean.mean;
            if (di == 0.0) least = std::min(least, g[i]);
            if (!(di < 0.0)) continue;
            for (std::size_t j = 0; j < m.size(); ++j) {
                const double dj = m[j] - mean.mean;
                if (!(dj > 0.0)) continue;
                const double share_i = dj / (dj - di);
                least = std::min(least, share_i * g[i] + (1.0 - share_i) * g[j]);
            }
        }
        return least;
    }
};

}  // namespace

SimplexFit simplex_least_squares(const std::vector<std::vector<double>>& columns, const std::vector<double>& target,
                                 const MixtureMean& mean, double relative_gap, double absolute_gap,
                                 int max_iterations) {
    if (columns.empty()) throw Error("internal: simplex_least_squares needs at least one column");
    for (const auto& c : columns)
        if (c.size() != target.size()) throw Error("internal: simplex_least_squares: a column's length is not the target's");
    if (!mean.column_means.empty()) {
        const auto [lo, hi] = std::minmax_element(mean.column_means.begin(), mean.column_means.end());
        if (mean.column_means.size() != columns.size() || !(mean.mean >= *lo && mean.mean <= *hi))
            throw Error("internal: simplex_least_squares: no mixture of the columns has that mean");
    }
    const Problem pr{columns, target, mean};
    const std::size_t n = columns.size();
    double step = 1.0 / pr.lipschitz();

    std::vector<double> p(n, 1.0 / double(n));
    project_to_simplex(p, mean);
    std::vector<double> y = p, previous = p;
    double t = 1.0, f_previous = Problem::value(pr.residual(p));
    SimplexFit best;
    best.weights = p;
    best.value = f_previous;
    auto certify = [&](const std::vector<double>& at, const std::vector<double>& r, double f) {
        // By convexity f* ≥ f(p) + ∇f(p)·(s* − p) for any p, feasible or not.
        const std::vector<double> g = pr.gradient(r);
        const double gap = std::inner_product(g.begin(), g.end(), at.begin(), 0.0) - pr.least_linear(g);
        best.lower_bound = std::max(best.lower_bound, f - gap);
        best.value = f;
        best.weights = at;
        return gap;
    };
    for (int it = 1; it <= max_iterations; ++it) {
        best.iterations = it;
        // The gradient step from the extrapolated point, projected.
        const std::vector<double> gy = pr.gradient(pr.residual(y));
        for (std::size_t j = 0; j < n; ++j) p[j] = y[j] - step * gy[j];
        project_to_simplex(p, mean);
        const std::vector<double> r = pr.residual(p);
        const double f = Problem::value(r);
        if (f > f_previous) {
            // Momentum overshot: restart from the last point. A plain step
            // (no momentum) that rises means the step is too long.
            if (t == 1.0) step *= 0.5;
            t = 1.0;
            y = previous;
            continue;
        }
        const double t_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
        for (std::size_t j = 0; j < n; ++j) y[j] = p[j] + (t - 1.0) / t_next * (p[j] - previous[j]);
        t = t_next;
        previous = p;
        f_previous = f;
        if (it % 10 == 0 && certify(p, r, f) <= std::max(relative_gap * f, absolute_gap)) return best;
    }
    certify(previous, pr.residual(previous), f_previous);
    return best;
}

}  // namespace jade
