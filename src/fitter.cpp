#include "jade/fitter.h"

#include "jade/error.h"
#include "jade/photo.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jade {

namespace {
const char* kChannel[3] = {"red", "green", "blue"};
}

DisplayStatistics display_statistics(const Film& film, float exposure) {
    DisplayStatistics s;
    std::vector<Rgb8> colours;
    std::array<double, 3> var_sum{}, bias_sum{};
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const float cov = film.coverage(x, y);
            if (cov < 0.5f) continue;
            // The object's own colour: a pixel the object only partly covers
            // holds colour × coverage when the background is left out.
            const Spectrum m = film.mean(x, y) * (exposure / cov);
            const Spectrum v = film.variance_of_mean(x, y);
            Rgb8 level;
            for (int c = 0; c < 3; ++c) {
                const double lin = std::clamp(double(m[c]), 0.0, 1.0);
                const double enc = srgb_encode(lin);
                level[c] = std::uint8_t(std::lround(255.0 * enc));
                // Delta method: Var[255 · srgb(e · x / cov)] ≈ (255 · srgb'(.) · e / cov)² Var[x],
                // and the mean of a noisy pixel's level is biased by ½ · 255 · srgb''(.) · (e / cov)² Var[x]
                // (sRGB is concave: noise lowers A). The bias is removed from A,
                // so that renders of different noise compare (the sRGB curve's
                // linear toe and the clamp at 1 have no second derivative).
                const double h = 1e-3;
                if (lin < 1.0 && std::isfinite(v[c])) {
                    const double lo = std::max(0.0, lin - h), hi = std::min(1.0, lin + h);
                    const double slope = 255.0 * (srgb_encode(hi) - srgb_encode(lo)) / (hi - lo);
                    const double g = slope * exposure / cov;
                    var_sum[c] += g * g * v[c];
                    if (lin - h > 0.0031308 && lin + h < 1.0) {
                        const double curv = 255.0 * (srgb_encode(lin + h) - 2 * srgb_encode(lin) + srgb_encode(lin - h)) / (h * h);
                        bias_sum[c] += 0.5 * curv * (exposure / cov) * (exposure / cov) * v[c];
                    }
                }
            }
            colours.push_back(level);
        }
    s.pixels = colours.size();
    s.histogram = RgbHistogram::of(colours);
    for (int c = 0; c < 3; ++c) {
        s.a[c] = s.pixels ? s.histogram.mean(c) - bias_sum[c] / double(s.pixels) : 0.0;
        s.a_sigma[c] = s.pixels ? std::sqrt(var_sum[c]) / double(s.pixels) : 0.0;
    }
    return s;
}

Spectrum photo_mean_linear(const Photo& photo) {
    double sum[3] = {0, 0, 0};
    std::size_t n = 0;
    for (std::size_t i = 0; i < photo.levels.size(); ++i) {
        if (!photo.foreground[i]) continue;
        for (int c = 0; c < 3; ++c) sum[c] += srgb_decode(photo.levels[i][c] / 255.0);
        ++n;
    }
    if (n == 0) return Spectrum(0.f);
    return Spectrum(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
}

Spectrum object_mean_linear(const Film& film) {
    double sum[3] = {0, 0, 0};
    std::size_t n = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const float cov = film.coverage(x, y);
            if (cov < 0.5f) continue;
            const Spectrum m = film.mean(x, y) / cov;
            for (int c = 0; c < 3; ++c) sum[c] += m[c];
            ++n;
        }
    if (n == 0) return Spectrum(0.f);
    return Spectrum(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
}

double exposure_for_brightness(const Film& film, int c, double target) {
    // The object's pixel values in channel c, once.
    std::vector<double> values;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const float cov = film.coverage(x, y);
            if (cov >= 0.5f) values.push_back(double(film.mean(x, y)[c]) / cov);
        }
    if (values.empty()) return 0.0;
    auto a_at = [&](double e) {
        double sum = 0;
        for (double v : values)
            sum += double(std::lround(255.0 * srgb_encode(std::clamp(e * v, 0.0, 1.0))));
        return sum / double(values.size());
    };
    double lo = std::log(1e-4), hi = std::log(1e4);
    if (a_at(std::exp(hi)) < target) return std::numeric_limits<double>::infinity();
    if (a_at(std::exp(lo)) > target) return 0.0;
    for (int i = 0; i < 50; ++i) {
        const double mid = 0.5 * (lo + hi);
        (a_at(std::exp(mid)) < target ? lo : hi) = mid;
    }
    return std::exp(0.5 * (lo + hi));
}

double exposure_in_reach(const Film& at_k_min, const Film& at_k_max,
                         const std::array<double, 3>& photo_a) {
    // A channel that no exposure in range can match (a render too dark even
    // at 10^4, or an empty one) pins its bound at that end of the range.
    constexpr double kLowest = 1e-4, kHighest = 1e4;
    double lower = kLowest, upper = kHighest;
    for (int c = 0; c < 3; ++c) {
        lower = std::max(lower, std::min(kHighest, exposure_for_brightness(at_k_max, c, photo_a[c])));
        upper = std::min(upper, std::max(kLowest, exposure_for_brightness(at_k_min, c, photo_a[c])));
    }
    return std::sqrt(lower * upper);
}

float matching_exposure(const Film& film, const Photo& photo) {
    auto luminance = [](const Spectrum& s) { return 0.2126 * s.x + 0.7152 * s.y + 0.0722 * s.z; };
    const double render = luminance(object_mean_linear(film));
    if (!(render > 0)) return 1.f;
    return float(luminance(photo_mean_linear(photo)) / render);
}

const char* to_string(FitMethod m) {
    switch (m) {
    case FitMethod::Step: return "step";
    case FitMethod::Bisect: return "bisect";
    case FitMethod::None: return "none";
    }
    return "?";
}

FitMethod parse_fit_method(const std::string& name) {
    if (name == "step") return FitMethod::Step;
    if (name == "bisect") return FitMethod::Bisect;
    if (name == "none") return FitMethod::None;
    throw Error("--fit must be 'bisect', 'step' or 'none', not '" + name + "'");
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

void FitDriver::observe(const std::array<double, 3>& delta_a) {
    for (int c = 0; c < 3; ++c)
        if (channel_[c].state == ChannelState::Searching) observe_channel(c, delta_a[c]);
}

void FitDriver::observe_bounds(const std::array<double, 3>& at_min, const std::array<double, 3>& at_max) {
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
            observe_channel(c, at_min[c]);  // reports it unreachable
        } else if (at_max[c] < 0) {  // darker at the largest
            k_[c] = limits_.k_max;
            observe_channel(c, at_max[c]);
        } else {
            ch.bracketed = true;
            ch.lo = limits_.k_min[c];
            ch.hi = limits_.k_max;
            k_[c] = 0.5 * (ch.lo + ch.hi);
        }
    }
}

void FitDriver::observe_channel(int c, double delta) {
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
        ch.reason = std::string(kChannel[c]) + ": the render is brighter than the photo even without " +
                    "scattering offset (k_s at its minimum, where sigma_s reaches 0): the photo is darker "
                    "than the material's absorption allows; raise --da or --density-scale";
        return;
    }
    if (dir > 0 && k >= limits_.k_max - 1e-12) {
        ch.state = ChannelState::Unreachable;
        ch.reason = std::string(kChannel[c]) + ": the render is darker than the photo even at k_s = " +
                    std::to_string(limits_.k_max) + ": the photo is brighter than any albedo the "
                    "material allows under this light; raise the light or lower --da";
        return;
    }

    if (method_ == FitMethod::Step) {
        // A sign change between two steps of Δk means the goal lies between
        // grid points the paper's step cannot land on.
        if (ch.have_prev && (ch.prev_delta > 0) != (delta > 0)) {
            ch.state = ChannelState::Unreachable;
            ch.reason = std::string(kChannel[c]) + ": one step of " + std::to_string(limits_.step) +
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

    // Bisect: first find a bracket, then halve it.
    if (!ch.bracketed && ch.have_prev && (ch.prev_delta > 0) != (delta > 0)) {
        ch.bracketed = true;
        ch.lo = delta < 0 ? k : ch.prev_k;
        ch.hi = delta < 0 ? ch.prev_k : k;
    } else if (ch.bracketed) {
        (delta < 0 ? ch.lo : ch.hi) = k;
    }
    if (ch.bracketed) {
        if (ch.hi - ch.lo < 1e-3) {
            ch.state = ChannelState::Unreachable;
            ch.reason = std::string(kChannel[c]) + ": A crosses the goal by more than the tolerance within " +
                        "k_s +- 0.001 (render noise or 8-bit quantisation), or the root moved outside the " +
                        "bracket; the best k_s is kept (raise --fit-spp or lower --fit-error)";
            return;
        }
        k_[c] = 0.5 * (ch.lo + ch.hi);
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
        ch.step = 2 * step;
        k_[c] = std::clamp(k + dir * step, limits_.k_min[c], limits_.k_max);
    }
}

}  // namespace jade
