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

// The Euclidean projection of `v` onto the probability simplex, in place.
void project_to_simplex(std::vector<double>& v);

// The Euclidean projection of `v` onto the simplex's points of mean
// `mean.mean`, in place.
void project_to_simplex(std::vector<double>& v, const MixtureMean& mean);

}  // namespace jade
