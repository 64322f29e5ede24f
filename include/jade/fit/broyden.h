#pragma once
// The Jacobian of two measured residuals in two unknowns, kept up to date
// by Broyden's rank-one update (Broyden 1965, the "good" update): each
// step's change of the residuals corrects J along the step and leaves it
// unchanged across it, so J learns the cross terms (how one lever moves the
// other residual) from steps that were taken anyway. --fit contrast solves
// (ΔA, ΔS) = 0 in (k_s, g) with one per channel (docs/design.md, "Contrast").
//
// The residuals come from Monte Carlo renders, so the update is guarded:
//   - each row learns only from a step that moved its residual, expected
//     (J·dx) or observed, by at least its `min_change` (in units of the
//     residuals): a smaller change is mostly noise. Per row, not for the
//     step as a whole: a step that moves A by several levels through k_s
//     and S by less than the noise through g teaches the A row and would
//     otherwise teach the S row a slope in k_s made of S's noise (Marble01
//     on the vase: S read 4.4 levels at g = 1 and 2.8 at g = 1.43, about
//     3.1·g give or take 0.6 from one render seed to the next; the S row
//     learned dS/dk_s = 34 and dS/dg = 2.5 from that, the next step asked
//     for g = 3.0 and S overshot the photo's 6.3 to 9.3);
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
    // changed (either row).
    // `min_change` per row: each residual's own noise sets how large a change
    // says something.
    bool update(const std::array<double, 2>& dx, const std::array<double, 2>& df,
                const std::array<double, 2>& min_change);
    bool update(const std::array<double, 2>& dx, const std::array<double, 2>& df, double min_change) {
        return update(dx, df, {min_change, min_change});
    }
};

}  // namespace jade
