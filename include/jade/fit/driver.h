#pragma once
// Drivers that move each channel's k_s until the render's brightness matches
// the photo's (paper §5.4, Algorithm 2; docs/design.md, "The fit").
//
//   A(κ) = Σ_i i · H(i, κ), gray levels 0..255, over the object's pixels
//   ΔA(κ) = A_render(κ) − A_photo(κ); goal |ΔA(κ)| < Δd = 1 gray level
//
// Brightness grows with k_s (more scattering, higher albedo), so a render
// brighter than the photo lowers k_s (the paper's Algorithm 2 prints the sign
// reversed; its text is right).

#include <array>
#include <string>

namespace jade {

// step     the paper's k_s driver (Algorithm 2), A only
// bisect   k_s for A by bracketing the root and narrowing the bracket
//          (false position, Illinois; the name is the flag's)
// contrast (default) bisect, then k_s and the contrast together for A and
//          S_material (fit/fit_session.h; docs/design.md, "Contrast")
// none     nothing fitted
enum class FitMethod { Step, Bisect, Contrast, None };
// Whether a method searches k_s by bisection (contrast does, first).
inline bool bisects(FitMethod m) { return m == FitMethod::Bisect || m == FitMethod::Contrast; }
const char* to_string(FitMethod m);
FitMethod parse_fit_method(const std::string& name);  // throws jade::Error

// Clipped: most of the photo's object pixels sit at level 0 or 255 in that
// channel, so its mean is only a bound and matching it proves nothing.
enum class ChannelState { Searching, Converged, Unreachable, Clipped };

struct FitLimits {
    std::array<double, 3> k_min{};  // smallest k_s per channel: σ_s ≥ 0 in every voxel
    double k_max = 4.0;             // largest k_s tried (paper units): albedo ~0.99 at v = 0.5
    double step = 0.01;             // the paper's Δk
    double tolerance = 1.0;         // Δd, gray levels
};

// Per-channel search for the k_s where ΔA changes sign, fed one measurement
// of ΔA for all three channels at a time (one render). Every channel searches
// independently; a channel that has converged or proved unreachable keeps its k_s.
//
//   step    the paper's driver: k -= Δk · sign(ΔA) after every render.
//   bisect  brackets the root, then narrows the bracket by false position:
//           the next k_s is where the chord through its ends crosses ΔA = 0,
//           and an end kept twice in a row has its ΔA halved (the Illinois
//           rule), so that the chord does not stall against one end where A
//           curves (it saturates in k_s). Where an end's render clips (most
//           of its pixels at level 0 or 255: its ΔA is only a bound, and A is
//           flat in k_s there) the bracket is halved instead: a chord through
//           such an end lands beside it again and again (a near-white
//           photo). Given renders at both bounds (observe_bounds), they are
//           the bracket. Otherwise it steps outward from the start, each step
//           at least double the last and at least 1.5x a secant estimate of
//           the distance to the root, until ΔA changes sign.
class FitDriver {
public:
    FitDriver(FitMethod method, const std::array<double, 3>& k_start, const FitLimits& limits);

    // The k_s to render next.
    const std::array<double, 3>& k() const { return k_; }
    // ΔA measured at k(); moves each searching channel on. clipped[c]: the
    // render clips in channel c, so its ΔA is only a bound.
    void observe(const std::array<double, 3>& delta_a, const std::array<bool, 3>& clipped = {});
    // Bisect only: ΔA measured at k_min and at k_max (two renders). A channel
    // whose signs differ is bracketed at once and narrowed from there; a
    // channel with the same sign at both ends is unreachable.
    void observe_bounds(const std::array<double, 3>& delta_at_min, const std::array<double, 3>& delta_at_max,
                        const std::array<bool, 3>& clipped_at_min = {},
                        const std::array<bool, 3>& clipped_at_max = {});
    bool done() const;
    ChannelState state(int c) const { return channel_[c].state; }
    // Why a channel stopped (empty while searching).
    const std::string& reason(int c) const { return channel_[c].reason; }
    // The k_s with the smallest |ΔA| seen per channel.
    const std::array<double, 3>& best_k() const { return best_k_; }

private:
    struct Channel {
        ChannelState state = ChannelState::Searching;
        std::string reason;
        bool have_prev = false;
        double prev_k = 0, prev_delta = 0;
        bool prev_clipped = false;
        double step = 0;
        bool bracketed = false;
        double lo = 0, hi = 0;      // ΔA(lo) < 0 < ΔA(hi)
        double d_lo = 0, d_hi = 0;  // ΔA at the ends, the one kept twice halved
        bool lo_clipped = false, hi_clipped = false;  // the end's render clips
        int kept = 0;               // the end kept by the last narrowing: -1 lo, +1 hi
    };
    void observe_channel(int c, double delta, bool clipped);
    void search_step(int c, double k, double delta, double dir, bool clipped);
    static void narrow(Channel& ch, double k, double delta, bool clipped);
    static double next_in_bracket(const Channel& ch);

    FitMethod method_;
    FitLimits limits_;
    std::array<double, 3> k_;
    std::array<Channel, 3> channel_;
    std::array<double, 3> best_k_, best_abs_;
};

}  // namespace jade
