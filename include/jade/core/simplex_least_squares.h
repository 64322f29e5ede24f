#pragma once
// Least squares over the probability simplex: the mixture weights p (p ≥ 0,
// Σ p = 1), optionally with a given mean (Σ p_j·m_j = m for given column
// means m_j), that bring K·p nearest to a target h, the columns of K being
// the mixture's components (histograms, say). The objective
// f(p) = |K·p − h|² is convex, so at any p the Frank–Wolfe gap over the
// feasible set F,
//     gap(p) = ∇f(p)·p − min_{s ∈ F} ∇f(p)·s ≥ f(p) − min_F f,
// certifies how far p still is from the best mixture: f(p) − gap(p) is a
// lower bound on what any mixture reaches (Jaggi 2013, "Revisiting
// Frank–Wolfe"). That bound is what a caller can quote as "no mixture gets
// below"; the minimiser is found by accelerated projected gradient (FISTA,
// Beck & Teboulle 2009, restarted whenever the objective rises, O'Donoghue &
// Candès 2015). The projection onto the simplex is Michelot's (1986), no
// sort; with the mean it is the simplex projection of y − μ·m for the μ, found by
// regula falsi, that gives the mean.

#include <vector>

namespace jade {

struct SimplexFit {
    std::vector<double> weights;  // p, on the simplex (and at the mean, to the root finder's precision)
    double value = 0.0;           // f(p) = |K·p − h|²
    double lower_bound = 0.0;     // f(p) − gap(p), at most min f (and ≥ 0)
    int iterations = 0;
};

// A mean the mixture must have: Σ p_j·column_means[j] = mean.
struct MixtureMean {
    std::vector<double> column_means;
    double mean = 0.0;
};

// `columns`: K's columns, each as long as `target`; at least one. `mean`:
// none when its column_means is empty, else one per column, and `mean` must
// lie between their least and greatest. Stops when the gap is at most the
// larger of `relative_gap` of f(p) and `absolute_gap`, or after
// `max_iterations`; either way `lower_bound` is a valid bound.
SimplexFit simplex_least_squares(const std::vector<std::vector<double>>& columns, const std::vector<double>& target,
                                 const MixtureMean& mean = {}, double relative_gap = 1e-2,
                                 double absolute_gap = 1e-6, int max_iterations = 20000);

// A second least-squares distance the mixture must keep under a ceiling:
// |M·p − g|² ≤ most, M's columns one per mixture component, each as long as
// this `target` g. A ceiling on a convex function leaves a convex set, so
// the problem stays convex.
struct MixtureNear {
    std::vector<std::vector<double>> columns;
    std::vector<double> target;
    double most = 0.0;
};

struct NearSimplexFit {
    bool feasible = false;  // the solver found a mixture under the ceiling (to within half the absolute gap)
    // The best such mixture found (`value` = |K·p − h|² of it: an upper
    // bound on the least), and a certified lower bound: no mixture at the
    // mean under the ceiling has |K·p − h|² below it. The bound holds
    // whether or not a mixture under the ceiling was found (+∞ for value
    // then).
    std::vector<double> weights;
    double value = 0.0, lower_bound = 0.0, second = 0.0;  // second: |M·p − g|² of weights
    int solves = 0;         // simplex_least_squares runs
};

// min |K·p − h|² over the simplex, at the mean, with |M·p − g|² ≤ most, by
// Lagrangian duality: for any λ ≥ 0 and any p under the ceiling,
// |K·p − h|² ≥ |K·p − h|² + λ·(|M·p − g|² − most), and the right side's
// least over the simplex is a least-squares fit of the stacked columns
// [K; √λ·M] to [h; √λ·g], less λ·most: one run of the solver, whose
// certified bound is a bound here. λ is bracketed by fourfold steps and
// bisected on its logarithm (|M·p − g|² at the minimiser falls as λ grows;
// a mixture counts as under the ceiling within half `absolute_gap`, since at
// a ceiling of 0 the distance only approaches it as λ grows without bound)
// until the best mixture under the ceiling and the best bound are within
// `relative_gap` of the value or `absolute_gap`, or after `max_solves` runs
// (of `max_iterations` each at most). Whenever it stops the bound holds.
NearSimplexFit simplex_least_squares_near(const std::vector<std::vector<double>>& columns,
                                          const std::vector<double>& target, const MixtureNear& near,
                                          const MixtureMean& mean = {}, double relative_gap = 1e-2,
                                          double absolute_gap = 1e-6, int max_solves = 16,
                                          int max_iterations = 20000);

// The Euclidean projection of `v` onto the probability simplex, in place.
void project_to_simplex(std::vector<double>& v);

// The Euclidean projection of `v` onto the simplex's points of mean
// `mean.mean`, in place.
void project_to_simplex(std::vector<double>& v, const MixtureMean& mean);

}  // namespace jade
