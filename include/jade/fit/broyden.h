#pragma once
// The Jacobian of two measured residuals in two unknowns, kept up to date
// by Broyden's rank-one update (Broyden 1965, the "good" update): each
// step's change of the residuals corrects J along the step and leaves it
// unchanged across it, so J learns the cross terms (how one lever moves the
// other residual) from steps that were taken anyway. --fit contrast solves
// (ΔA, ΔS) = 0 in (k_s, g) with one per channel (docs/design.md, "Contrast").
//
// The residuals come from Monte Carlo renders, so the update is guarded:
//   - a step whose expected effect is within `min_change` of nothing (in
//     units of the residuals) leaves J as it is: its change is mostly noise;
//   - each row's own lever (the diagonal) keeps its sign and changes by at
//     most a factor of 4 per update;
//   - the cross terms are shrunk where they would bring J near singular
//     (det below a quarter of the diagonals' product), so that a Newton
//     step stays within a few times the one-dimensional steps.

#include <array>

namespace jade {

struct BroydenJacobian2 {
    // m[i][j] = ∂f_i/∂x_j; the diagonal must be positive (each residual
    // grows with its own unknown).
    std::array<std::array<double, 2>, 2> m{};

    double det() const { return m[0][0] * m[1][1] - m[0][1] * m[1][0]; }
    // The Newton step d with J·d = −f.
    std::array<double, 2> newton_step(const std::array<double, 2>& f) const;
    // After a step dx changed the residuals by df. The update's norm weighs
    // each unknown by its own diagonal (a unit in either is one unit of its
    // own residual), so the unknowns' units do not matter. Returns whether J
    // changed.
    bool update(const std::array<double, 2>& dx, const std::array<double, 2>& df, double min_change);
};

}  // namespace jade
