#include "jade/fit/display.h"

#include "jade/core/display.h"
#include "jade/core/error.h"
#include "jade/volume/photo.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jade {

DisplayStatistics display_statistics(const Film& film, float exposure) {
    DisplayStatistics s;
    std::vector<Rgb8> colours;
    std::array<double, 3> var_sum{}, bias_sum{};
    s.luma.width = film.width();
    s.luma.height = film.height();
    s.luma.values.assign(std::size_t(film.width()) * film.height(), 0.f);
    s.luma.mask.assign(s.luma.values.size(), 0);
    double luma_var_sum = 0.0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const float cov = film.coverage(x, y);
            if (!is_object_pixel(cov)) continue;
            // The object's own colour: a pixel the object only partly covers
            // holds colour × coverage when the background is left out.
            const Spectrum m = film.mean(x, y) * (exposure / cov);
            const Spectrum v = film.variance_of_mean(x, y);
            Rgb8 level;
            std::array<double, 3> level_sigma{};
            for (int c = 0; c < 3; ++c) {
                const double lin = std::clamp(double(m[c]), 0.0, 1.0);
                level[c] = display_level(lin);
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
                    level_sigma[c] = g * std::sqrt(double(v[c]));
                    if (lin - h > 0.0031308 && lin + h < 1.0) {
                        const double curv = 255.0 * (srgb_encode(lin + h) - 2 * srgb_encode(lin) + srgb_encode(lin - h)) / (h * h);
                        bias_sum[c] += 0.5 * curv * (exposure / cov) * (exposure / cov) * v[c];
                    }
                }
            }
            colours.push_back(level);
            const std::size_t i = std::size_t(y) * film.width() + x;
            s.luma.values[i] = float(luma(level[0], level[1], level[2]));
            s.luma.mask[i] = 1;
            const double luma_sigma = luma(level_sigma[0], level_sigma[1], level_sigma[2]);
            luma_var_sum += luma_sigma * luma_sigma;
        }
    s.pixels = colours.size();
    s.histogram = RgbHistogram::of(colours);
    for (int c = 0; c < 3; ++c) {
        s.a[c] = s.pixels ? s.histogram.mean(c) - bias_sum[c] / double(s.pixels) : 0.0;
        s.a_sigma[c] = s.pixels ? std::sqrt(var_sum[c]) / double(s.pixels) : 0.0;
        const double spread = s.histogram.spread(c);
        s.s[c] = s.pixels ? std::sqrt(std::max(0.0, spread * spread - var_sum[c] / double(s.pixels))) : 0.0;
    }
    s.luma_noise_variance = s.pixels ? luma_var_sum / double(s.pixels) : 0.0;
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
            if (!is_object_pixel(cov)) continue;
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
            if (is_object_pixel(cov)) values.push_back(double(film.mean(x, y)[c]) / cov);
        }
    if (values.empty()) return 0.0;
    auto a_at = [&](double e) {
        double sum = 0;
        for (double v : values)
            sum += double(display_level(e * v));
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

}  // namespace jade
