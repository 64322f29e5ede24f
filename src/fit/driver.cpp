#include "jade/fit/driver.h"

#include "jade/core/error.h"
#include "jade/core/spectrum.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jade {

const char* to_string(FitMethod m) {
    switch (m) {
    case FitMethod::Step: return "step";
    case FitMethod::Bisect: return "bisect";
    case FitMethod::Contrast: return "contrast";
    case FitMethod::None: return "none";
    }
    return "?";
}

FitMethod parse_fit_method(const std::string& name) {
    if (name == "step") return FitMethod::Step;
    if (name == "bisect") return FitMethod::Bisect;
    if (name == "contrast") return FitMethod::Contrast;
    if (name == "none") return FitMethod::None;
    throw Error("--fit must be 'contrast', 'bisect', 'step' or 'none', not '" + name + "'");
}

FitDriver::FitDriver(FitMethod method, const std::array<double, 3>& k_start, const FitLimits& limits)
    : method_(method), limits_(limits), k_(k_start) {
    for (int c = 0; c < 3; ++c) {
        k_[c] = std::clamp(k_[c], limits.k_min[c], limits.k_max);
        best_k_[c] = k_[c];
        best_abs_[c] = std::numeric_limits<double>::infinity();
        channel_[c].step = limits.step;
        if (method == FitMethod::None) {
            channel_[c].state = ChannelState::Converged;
            channel_[c].reason = "not fitted (--fit none)";
        }
    }
}

bool FitDriver::done() const {
    return std::all_of(channel_.begin(), channel_.end(),
                       [](const Channel& ch) { return ch.state != ChannelState::Searching; });
}

void FitDriver::observe(const std::array<double, 3>& delta_a, const std::array<bool, 3>& clipped) {
    for (int c = 0; c < 3; ++c)
        if (channel_[c].state == ChannelState::Searching) observe_channel(c, delta_a[c], clipped[c]);
}

void FitDriver::observe_bounds(const std::array<double, 3>& at_min, const std::array<double, 3>& at_max,
                               const std::array<bool, 3>& clipped_at_min, const std::array<bool, 3>& clipped_at_max) {
    for (int c = 0; c < 3; ++c) {
        Channel& ch = channel_[c];
        if (ch.state != ChannelState::Searching) continue;
        for (const auto& [k, delta] : {std::pair{limits_.k_min[c], at_min[c]}, std::pair{limits_.k_max, at_max[c]}})
            if (std::abs(delta) < best_abs_[c]) {
                best_abs_[c] = std::abs(delta);
                best_k_[c] = k;
            }
        if (best_abs_[c] < limits_.tolerance) {
            ch.state = ChannelState::Converged;
            k_[c] = best_k_[c];
            continue;
        }
        if (at_min[c] > 0) {  // brighter than the photo at the smallest k_s
            k_[c] = limits_.k_min[c];
            observe_channel(c, at_min[c], clipped_at_min[c]);  // reports it unreachable
        } else if (at_max[c] < 0) {  // darker at the largest
            k_[c] = limits_.k_max;
            observe_channel(c, at_max[c], clipped_at_max[c]);
        } else {
            ch.bracketed = true;
            ch.lo = limits_.k_min[c];
            ch.d_lo = at_min[c];
            ch.lo_clipped = clipped_at_min[c];
            ch.hi = limits_.k_max;
            ch.d_hi = at_max[c];
            ch.hi_clipped = clipped_at_max[c];
            k_[c] = next_in_bracket(ch);
        }
    }
}

void FitDriver::observe_channel(int c, double delta, bool clipped) {
    Channel& ch = channel_[c];
    const double k = k_[c];
    if (std::abs(delta) < best_abs_[c]) {
        best_abs_[c] = std::abs(delta);
        best_k_[c] = k;
    }
    if (std::abs(delta) < limits_.tolerance) {
        ch.state = ChannelState::Converged;
        return;
    }
    const double dir = delta > 0 ? -1.0 : 1.0;  // brighter than the photo: lower k_s
    // At a bound, still on the same side: no k_s in range reaches the photo.
    if (dir < 0 && k <= limits_.k_min[c] + 1e-12) {
        ch.state = ChannelState::Unreachable;
        ch.reason = std::string(channel_name(c)) + ": the render is brighter than the photo even without " +
                    "scattering offset (k_s at its minimum, where sigma_s reaches 0): the photo is darker "
                    "than the material's absorption allows; raise --da or --density-scale";
        return;
    }
    if (dir > 0 && k >= limits_.k_max - 1e-12) {
        ch.state = ChannelState::Unreachable;
        ch.reason = std::string(channel_name(c)) + ": the render is darker than the photo even at k_s = " +
                    std::to_string(limits_.k_max) + ": the photo is brighter than any albedo the "
                    "material allows under this light; raise the light or lower --da";
        return;
    }

    if (method_ == FitMethod::Step) {
        // A sign change between two steps of Δk means the goal lies between
        // grid points the paper's step cannot land on.
        if (ch.have_prev && (ch.prev_delta > 0) != (delta > 0)) {
            ch.state = ChannelState::Unreachable;
            ch.reason = std::string(channel_name(c)) + ": one step of " + std::to_string(limits_.step) +
                        " moves A by more than " + std::to_string(2 * limits_.tolerance) +
                        " gray levels, so the step driver cannot meet |dA| < " +
                        std::to_string(limits_.tolerance) + "; the best k_s is kept (try --fit bisect)";
            return;
        }
        ch.have_prev = true;
        ch.prev_k = k;
        ch.prev_delta = delta;
        k_[c] = std::clamp(k + dir * limits_.step, limits_.k_min[c], limits_.k_max);
        return;
    }

    search_step(c, k, delta, dir, clipped);
}

// Bisect: first find a bracket, stepping outward, then narrow it.
void FitDriver::search_step(int c, double k, double delta, double dir, bool clipped) {
    Channel& ch = channel_[c];
    if (!ch.bracketed && ch.have_prev && (ch.prev_delta > 0) != (delta > 0)) {
        ch.bracketed = true;
        ch.lo = delta < 0 ? k : ch.prev_k;
        ch.d_lo = delta < 0 ? delta : ch.prev_delta;
        ch.lo_clipped = delta < 0 ? clipped : ch.prev_clipped;
        ch.hi = delta < 0 ? ch.prev_k : k;
        ch.d_hi = delta < 0 ? ch.prev_delta : delta;
        ch.hi_clipped = delta < 0 ? ch.prev_clipped : clipped;
    } else if (ch.bracketed) {
        narrow(ch, k, delta, clipped);
    }
    if (ch.bracketed) {
        if (ch.hi - ch.lo < 1e-3) {
            ch.state = ChannelState::Unreachable;
            ch.reason = std::string(channel_name(c)) + ": A crosses the goal by more than the tolerance within " +
                        "k_s +- 0.001 (render noise or 8-bit quantisation), or the root moved outside the " +
                        "bracket; the best k_s is kept (raise --fit-spp or lower --fit-error)";
            return;
        }
        k_[c] = next_in_bracket(ch);
    } else {
        double step = ch.step;
        if (ch.have_prev && delta != ch.prev_delta) {
            // Secant estimate of the distance to the root, overshot by half so
            // that the next render lands past it and closes the bracket.
            const double slope = (delta - ch.prev_delta) / (k - ch.prev_k);
            // Capped at 8 doubling steps' worth: where A flattens out the
            // secant would leap far past the root.
            if (slope > 0) step = std::max(step, std::min(1.5 * std::abs(delta / slope), 8 * step));
        }
        ch.have_prev = true;
        ch.prev_k = k;
        ch.prev_delta = delta;
        ch.prev_clipped = clipped;
        ch.step = 2 * step;
        k_[c] = std::clamp(k + dir * step, limits_.k_min[c], limits_.k_max);
    }
}

// k replaces the end on its side of the root; the end kept, if it was
// kept the time before too, has its ΔA halved (Illinois).
void FitDriver::narrow(Channel& ch, double k, double delta, bool clipped) {
    const int kept = delta < 0 ? +1 : -1;
    if (kept == ch.kept) (kept > 0 ? ch.d_hi : ch.d_lo) *= 0.5;
    ch.kept = kept;
    (delta < 0 ? ch.lo : ch.hi) = k;
    (delta < 0 ? ch.d_lo : ch.d_hi) = delta;
    (delta < 0 ? ch.lo_clipped : ch.hi_clipped) = clipped;
}

// Where the chord through the bracket's ends crosses ΔA = 0, held
// kHeldIn of the bracket in from either end (the chord of a channel whose
// ends differ by a few levels of noise could land on an end, where a render
// teaches nothing); the middle where an end's ΔA is only a bound.
double FitDriver::next_in_bracket(const Channel& ch) {
    constexpr double kHeldIn = 0.02;
    if (ch.lo_clipped || ch.hi_clipped) return 0.5 * (ch.lo + ch.hi);
    const double t = ch.d_lo / (ch.d_lo - ch.d_hi);  // in (0, 1): d_lo < 0 < d_hi
    return ch.lo + std::clamp(t, kHeldIn, 1.0 - kHeldIn) * (ch.hi - ch.lo);
}

}  // namespace jade
