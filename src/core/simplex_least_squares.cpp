#include "jade/core/simplex_least_squares.h"

#include "jade/core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace jade {

void project_to_simplex(std::vector<double>& v) {
    // The projection is max(v − τ, 0) with τ set so that the result sums to
    // 1. Michelot's iteration (1986), without a sort: over a set of
    // candidates that holds every element the projection keeps, τ from the
    // candidates' sum is at most the true one (the others add at most τ
    // each), so those at or below it are not kept either; drop them and
    // repeat until none drops. It starts from the elements above
    // max(v) − 1, since the largest keeps at most 1: τ ≥ max(v) − 1.
    // The fit projects thousands of times over 2 000 columns, where a sort
    // each time was most of its time.
    if (v.empty()) return;
    const double least_tau = *std::max_element(v.begin(), v.end()) - 1.0;
    std::vector<double> candidates;
    candidates.reserve(v.size());
    for (double x : v)
        if (x > least_tau) candidates.push_back(x);
    double tau = least_tau;
    for (;;) {
        const double sum = std::accumulate(candidates.begin(), candidates.end(), 0.0);
        tau = (sum - 1.0) / double(candidates.size());
        const auto kept = std::remove_if(candidates.begin(), candidates.end(), [tau](double x) { return x <= tau; });
        if (kept == candidates.end()) break;
        candidates.erase(kept, candidates.end());
    }
    for (double& x : v) x = std::max(x - tau, 0.0);
}

namespace {

// The projection onto the simplex's points of mean `mean.mean`, in place,
// from a guess of its multiplier μ (below); returns μ. KKT:
// p = max(v − τ − μ·m, 0), τ the simplex projection's for that μ; the mean
// of p falls as μ grows, piecewise linearly.
double project_at_mean(std::vector<double>& v, const MixtureMean& mean, double guess) {
    const std::vector<double>& m = mean.column_means;
    auto at = [&](double mu) {
        std::vector<double> p(v.size());
        for (std::size_t j = 0; j < v.size(); ++j) p[j] = v[j] - mu * m[j];
        project_to_simplex(p);
        return p;
    };
    auto excess = [&](const std::vector<double>& p) {
        return std::inner_product(p.begin(), p.end(), m.begin(), 0.0) - mean.mean;
    };
    // A bracket about the guess, widened by doubling: a fit projects from
    // one step to the next, where μ moves little, and a bracket about the
    // last μ took a few projections where one from (−1, 1) took thirty.
    // Then regula falsi with the Illinois halving, to a mean within 10⁻⁹ of
    // the scale of the column means.
    const double tolerance = 1e-9 * std::max(1.0, std::abs(mean.mean));
    std::vector<double> p = at(guess);
    double e = excess(p);
    if (std::abs(e) <= tolerance) {
        v = std::move(p);
        return guess;
    }
    double width = guess != 0.0 ? 1e-2 * std::abs(guess) : 1.0;
    double lo = guess, hi = guess, e_lo = e, e_hi = e;
    for (int i = 0; i < 400 && e_lo < 0.0; ++i, width *= 2.0) e_lo = excess(at(lo = guess - width));
    for (int i = 0; i < 400 && e_hi > 0.0; ++i, width *= 2.0) e_hi = excess(at(hi = guess + width));
    double mu = e_lo == 0.0 ? lo : hi;
    bool at_mu = false;  // p is the projection at mu
    int side = 0;
    for (int i = 0; i < 200 && hi - lo > 1e-15 * std::max(std::abs(lo), std::abs(hi)); ++i) {
        mu = std::clamp(e_lo == e_hi ? 0.5 * (lo + hi) : (lo * e_hi - hi * e_lo) / (e_hi - e_lo), lo, hi);
        p = at(mu);
        at_mu = true;
        e = excess(p);
        if (std::abs(e) <= tolerance) break;
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
    v = at_mu ? std::move(p) : at(mu);
    return mu;
}

}  // namespace

void project_to_simplex(std::vector<double>& v, const MixtureMean& mean) {
    if (mean.column_means.empty()) return project_to_simplex(v);
    project_at_mean(v, mean, 0.0);
}

namespace {

struct Problem {
    const std::vector<std::vector<double>>& k;
    const std::vector<double>& h;
    const MixtureMean& mean;

    // Where each column is not zero, [first, last): a histogram of levels
    // scaled far up or down sits in a few bins, and the products below
    // skip the rest.
    struct Span {
        std::size_t first = 0, last = 0;
    };
    std::vector<Span> spans;

    void find_spans() {
        spans.resize(k.size());
        for (std::size_t j = 0; j < k.size(); ++j) {
            const auto nonzero = [](double x) { return x != 0.0; };
            const auto first = std::find_if(k[j].begin(), k[j].end(), nonzero);
            const auto last = std::find_if(k[j].rbegin(), k[j].rend(), nonzero).base();
            spans[j] = first < last ? Span{std::size_t(first - k[j].begin()), std::size_t(last - k[j].begin())} : Span{};
        }
    }

    // r = K·p − h
    std::vector<double> residual(const std::vector<double>& p) const {
        std::vector<double> r(h.size());
        for (std::size_t i = 0; i < h.size(); ++i) r[i] = -h[i];
        for (std::size_t j = 0; j < k.size(); ++j) {
            if (p[j] == 0.0) continue;
            for (std::size_t i = spans[j].first; i < spans[j].last; ++i) r[i] += p[j] * k[j][i];
        }
        return r;
    }
    // ∇f = 2·Kᵀ·r
    std::vector<double> gradient(const std::vector<double>& r) const {
        std::vector<double> g(k.size());
        for (std::size_t j = 0; j < k.size(); ++j) {
            const Span& s = spans[j];
            g[j] = 2.0 * dot(k[j].data() + s.first, r.data() + s.first, s.last - s.first);
        }
        return g;
    }
    // a·b over n values in four running sums: one sum waits on every
    // addition before it, four let the additions overlap (this product is
    // most of the fit's time).
    static double dot(const double* a, const double* b, std::size_t n) {
        double s[4] = {0.0, 0.0, 0.0, 0.0};
        std::size_t i = 0;
        for (; i + 4 <= n; i += 4)
            for (std::size_t u = 0; u < 4; ++u) s[u] += a[i + u] * b[i + u];
        for (; i < n; ++i) s[0] += a[i] * b[i];
        return (s[0] + s[1]) + (s[2] + s[3]);
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
    // either side of it mixed to the mean, whose g·s is the line between
    // the points (m_i, g_i) and (m_j, g_j) read at the mean. The least of
    // those is the lower convex hull of the points read there: one pass
    // over the points in order of m (by_mean), where every pair took
    // n² / 4 steps (a million over the fit's 2 000 columns).
    double least_linear(const std::vector<double>& g) const {
        if (mean.column_means.empty()) return *std::min_element(g.begin(), g.end());
        const std::vector<double>& m = mean.column_means;
        const double at = mean.mean;
        // The lower hull, left to right; of points at one m, the lowest.
        std::vector<std::size_t> hull;
        auto below = [&](std::size_t a, std::size_t b, std::size_t c) {
            // b on or above the line from a to c: not on the lower hull.
            return (g[b] - g[a]) * (m[c] - m[a]) >= (g[c] - g[a]) * (m[b] - m[a]);
        };
        for (std::size_t j : by_mean) {
            if (!hull.empty() && m[hull.back()] == m[j]) {
                if (g[j] >= g[hull.back()]) continue;
                hull.pop_back();
            }
            while (hull.size() >= 2 && below(hull[hull.size() - 2], hull.back(), j)) hull.pop_back();
            hull.push_back(j);
        }
        // The hull's edge over the mean (between the least and greatest m:
        // the caller checked).
        const auto right = std::find_if(hull.begin(), hull.end(), [&](std::size_t j) { return m[j] >= at; });
        if (m[*right] == at || right == hull.begin()) return g[*right];
        const std::size_t i = *(right - 1), j = *right;
        const double share_i = (m[j] - at) / (m[j] - m[i]);
        return share_i * g[i] + (1.0 - share_i) * g[j];
    }

    // The columns in order of their means (with a mean).
    std::vector<std::size_t> by_mean;
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
    Problem pr{columns, target, mean, {}, {}};
    pr.find_spans();
    if (!mean.column_means.empty()) {
        pr.by_mean.resize(columns.size());
        std::iota(pr.by_mean.begin(), pr.by_mean.end(), std::size_t(0));
        std::stable_sort(pr.by_mean.begin(), pr.by_mean.end(), [&](std::size_t a, std::size_t b) {
            return mean.column_means[a] < mean.column_means[b];
        });
    }
    const std::size_t n = columns.size();
    double step = 1.0 / pr.lipschitz();

    // The projection, with the mean from the last step's multiplier.
    double mu = 0.0;
    auto project = [&](std::vector<double>& v) {
        if (mean.column_means.empty())
            project_to_simplex(v);
        else
            mu = project_at_mean(v, mean, mu);
    };
    std::vector<double> p(n, 1.0 / double(n));
    project(p);
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
        project(p);
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

namespace {

double squared_distance(const std::vector<std::vector<double>>& columns, const std::vector<double>& target,
                        const std::vector<double>& p) {
    std::vector<double> r(target.size());
    for (std::size_t i = 0; i < target.size(); ++i) r[i] = -target[i];
    for (std::size_t j = 0; j < columns.size(); ++j)
        if (p[j] != 0.0)
            for (std::size_t i = 0; i < target.size(); ++i) r[i] += p[j] * columns[j][i];
    return std::inner_product(r.begin(), r.end(), r.begin(), 0.0);
}

}  // namespace

NearSimplexFit simplex_least_squares_near(const std::vector<std::vector<double>>& columns,
                                          const std::vector<double>& target, const MixtureNear& near,
                                          const MixtureMean& mean, double relative_gap, double absolute_gap,
                                          int max_solves, int max_iterations) {
    if (near.columns.size() != columns.size())
        throw Error("internal: simplex_least_squares_near needs one second column per column");
    for (const auto& c : near.columns)
        if (c.size() != near.target.size())
            throw Error("internal: simplex_least_squares_near: a second column's length is not its target's");
    NearSimplexFit out;
    out.value = std::numeric_limits<double>::infinity();
    double best_lower = 0.0;
    // Solves at λ; returns |M·p − g|² at the minimiser, and keeps both bounds.
    auto take = [&](double lambda) {
        const double w = std::sqrt(lambda);
        std::vector<std::vector<double>> stacked(columns.size());
        for (std::size_t j = 0; j < columns.size(); ++j) {
            stacked[j] = columns[j];
            for (double x : near.columns[j]) stacked[j].push_back(w * x);
        }
        std::vector<double> both = target;
        for (double x : near.target) both.push_back(w * x);
        ++out.solves;
        // Each run to half the gap asked for, so that the two bounds can
        // meet within it.
        const SimplexFit fit =
            simplex_least_squares(stacked, both, mean, 0.5 * relative_gap, 0.5 * absolute_gap, max_iterations);
        best_lower = std::max(best_lower, fit.lower_bound - lambda * near.most);
        const double second = squared_distance(near.columns, near.target, fit.weights);
        // Under the ceiling to within the gap asked for: at a ceiling of 0
        // (a material exactly the photo's) the second distance only
        // approaches it as λ grows without bound.
        if (second <= near.most + 0.5 * absolute_gap) {
            const double f = squared_distance(columns, target, fit.weights);
            if (f < out.value) out.value = f, out.weights = fit.weights, out.second = second, out.feasible = true;
        }
        return second;
    };
    auto close_enough = [&] {
        return out.value - best_lower <= std::max(relative_gap * out.value, absolute_gap);
    };
    if (take(0.0) > near.most + 0.5 * absolute_gap) {
        // The ceiling binds. λ = 1 weighs the two distances alike; up by
        // fourfold steps until the minimiser is under the ceiling, then
        // halve the bracket on log λ.
        double lo = 0.0, hi = 1.0;
        const double ceiling = near.most + 0.5 * absolute_gap;
        while (out.solves < max_solves && take(hi) > ceiling) lo = hi, hi *= 4.0;
        while (out.solves < max_solves && !close_enough()) {
            const double mid = lo > 0.0 ? std::sqrt(lo * hi) : 0.25 * hi;
            (take(mid) > ceiling ? lo : hi) = mid;
        }
    }
    out.lower_bound = best_lower;
    return out;
}

}  // namespace jade
