#include "jade/fit/display.h"

#include "jade/core/display.h"
#include "jade/core/error.h"
#include "jade/core/simplex_least_squares.h"
#include "jade/volume/histogram.h"
#include "jade/volume/photo.h"
#include "jade/volume/structure_estimate.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace jade {

namespace {

// A pixel's 8-bit display levels from its linear colour (exposed, and
// divided by its coverage), clamped at white.
Rgb8 display_levels(const Spectrum& linear) {
    Rgb8 level;
    for (int c = 0; c < 3; ++c) level[c] = display_level(std::clamp(double(linear[c]), 0.0, 1.0));
    return level;
}

// The object's luma from replicates 0–1 and from 2–3 (render/film.h), over
// the pixels `mask` marks; none unless every replicate of every pixel holds
// a whole turn of the heroes.
std::array<GrayImage, 2> luma_halves(const Film& film, float exposure, const GrayImage& mask) {
    if (film.fewest_samples() < Film::kReplicates * Film::kStrata) return {};
    std::array<GrayImage, 2> halves{mask, mask};
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const std::size_t i = std::size_t(y) * film.width() + x;
            if (!mask.mask[i]) continue;
            const float scale = exposure / film.coverage(x, y);
            for (int h = 0; h < 2; ++h) {
                const Rgb8 level = display_levels(film.replicates_mean(x, y, 2 * h, 2) * scale);
                halves[h].values[i] = float(luma(level[0], level[1], level[2]));
            }
        }
    return halves;
}

}  // namespace

DisplayStatistics display_statistics(const Film& film, float exposure, LumaHalves halves) {
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
            const Rgb8 level = display_levels(m);
            std::array<double, 3> level_sigma{};
            for (int c = 0; c < 3; ++c) {
                const double lin = std::clamp(double(m[c]), 0.0, 1.0);
                // Delta method: Var[255 · srgb(e · x / cov)] ≈ (255 · srgb'(.) · e / cov)² Var[x],
                // and the mean of a noisy pixel's level is biased by ½ · 255 · srgb''(.) · (e / cov)² Var[x]
                // (sRGB is concave: noise lowers A). The bias is removed from A,
                // so that renders of different noise compare (the sRGB curve's
                // linear toe and the clamp at 1 have no second derivative).
                const double h = 1e-3;
                if (lin < 1.0 && std::isfinite(v[c])) {
                    const double g = level_slope(lin) * exposure / cov;
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
    if (halves == LumaHalves::Measure) s.luma_halves = luma_halves(film, exposure, s.luma);
    return s;
}

std::array<double, 3> extrapolated_brightness(const SplitFilms& render, float exposure) {
    const DisplayStatistics whole = display_statistics(render.merged(), exposure);
    const DisplayStatistics first = display_statistics(render.first, exposure);
    const DisplayStatistics second = display_statistics(render.second, exposure);
    std::array<double, 3> a{};
    for (int c = 0; c < 3; ++c)
        a[c] = 2.0 * whole.histogram.mean(c) - 0.5 * (first.histogram.mean(c) + second.histogram.mean(c));
    return a;
}

std::array<double, 3> noise_clipped_share(const SplitFilms& render, float exposure) {
    const Film& a = render.first;
    const Film& b = render.second;
    std::array<std::size_t, 3> split{};
    std::size_t pixels = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const float cov_a = a.coverage(x, y), cov_b = b.coverage(x, y);
            // The halves hold equally many samples: their mean coverage is the whole render's.
            if (!is_object_pixel(0.5f * (cov_a + cov_b)) || !(cov_a > 0.f) || !(cov_b > 0.f)) continue;
            ++pixels;
            const Rgb8 la = display_levels(a.mean(x, y) * (exposure / cov_a));
            const Rgb8 lb = display_levels(b.mean(x, y) * (exposure / cov_b));
            for (int c = 0; c < 3; ++c) split[c] += (la[c] == 255) != (lb[c] == 255);
        }
    std::array<double, 3> share{};
    for (int c = 0; c < 3; ++c) share[c] = pixels ? double(split[c]) / double(pixels) : 0.0;
    return share;
}

double level_slope(double linear) {
    if (linear >= 1.0) return 0.0;
    const double h = 1e-3;
    const double lo = std::max(0.0, linear - h), hi = std::min(1.0, linear + h);
    return 255.0 * (srgb_encode(hi) - srgb_encode(lo)) / (hi - lo);
}

namespace {

// One channel of a render over the object's pixels: exposed linear values
// divided by coverage, and which pixels are the object's.
struct ObjectChannel {
    int width = 0, height = 0;
    std::vector<double> value;
    std::vector<std::uint8_t> inside;
};

// `image`: linear RGBA, alpha = coverage (Film::rgba(true)).
ObjectChannel object_channel(const ImageF32& image, int c, float exposure) {
    ObjectChannel o;
    o.width = image.width;
    o.height = image.height;
    const std::size_t n = std::size_t(o.width) * o.height;
    o.value.assign(n, 0.0);
    o.inside.assign(n, 0);
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            const float cov = image.at(x, y, 3);
            if (!is_object_pixel(cov)) continue;
            const std::size_t i = std::size_t(y) * o.width + x;
            const double scale = exposure / cov;
            o.value[i] = image.at(x, y, c) * scale;
            o.inside[i] = 1;
        }
    return o;
}

ImageF32 film_image(const Film& film) { return ImageF32{film.width(), film.height(), 4, film.rgba(true)}; }

// The mean of the object's pixels in each b×b block of the image (blocks at
// least half the object's).
ObjectChannel block_means(const ObjectChannel& in, int b) {
    ObjectChannel out;
    out.width = in.width / b;
    out.height = in.height / b;
    const std::size_t n = std::size_t(out.width) * out.height;
    out.value.assign(n, 0.0);
    out.inside.assign(n, 0);
    for (int by = 0; by < out.height; ++by)
        for (int bx = 0; bx < out.width; ++bx) {
            double sum = 0.0;
            int count = 0;
            for (int y = by * b; y < (by + 1) * b; ++y)
                for (int x = bx * b; x < (bx + 1) * b; ++x) {
                    const std::size_t j = std::size_t(y) * in.width + x;
                    if (!in.inside[j]) continue;
                    sum += in.value[j];
                    ++count;
                }
            if (2 * count < b * b) continue;
            const std::size_t i = std::size_t(by) * out.width + bx;
            out.value[i] = sum / count;
            out.inside[i] = 1;
        }
    return out;
}

// The mean display level of `scale` × the inside values.
double mean_level(const ObjectChannel& f, double scale) {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < f.inside.size(); ++i)
        if (f.inside[i]) sum += continuous_level(scale * f.value[i]), ++n;
    return n ? sum / double(n) : 0.0;
}

// The mean display level of `scale` × the inside values, and its
// derivative with respect to log(scale).
LevelSlope mean_level_slope(const ObjectChannel& f, double scale) {
    LevelSlope sum{0.0, 0.0};
    std::size_t n = 0;
    for (std::size_t i = 0; i < f.inside.size(); ++i)
        if (f.inside[i]) {
            const LevelSlope l = continuous_level_slope(scale * f.value[i]);
            sum.level += l.level, sum.slope += l.slope, ++n;
        }
    return n ? LevelSlope{sum.level / double(n), sum.slope / double(n)} : LevelSlope{0.0, 0.0};
}

// The scale of the inside values that gives them the mean display level
// `target`, to a relative 10^-9, within 10^-6..10^6. The mean level grows
// with the scale: Newton's method on its logarithm t (the level's slope in t
// comes with the level from the same pass over the pixels), inside a
// bracket every pass narrows, bisecting where a step would leave it or the
// slope is 0 (every pixel clipped). Each pass is an sRGB encoding per pixel
// and the fit flattens 21 images per block size a step: 5–8 passes on the
// fitter's tests where bisection alone took 35 (seconds a step on one core
// at 512²), 21–38 on the few whose target lies near the range's edge.
double scale_to_mean_level(const ObjectChannel& f, double target) {
    constexpr double kLogTolerance = 1e-9;
    // Far more than bisection alone needs (35): a bound, not a budget.
    constexpr int kMaxPasses = 200;
    double lo = std::log(1e-6), hi = std::log(1e6), t = 0.0;
    for (int pass = 0; pass < kMaxPasses && hi - lo > kLogTolerance; ++pass) {
        const LevelSlope m = mean_level_slope(f, std::exp(t));
        (m.level < target ? lo : hi) = t;
        double next = m.slope > 0.0 ? t + (target - m.level) / m.slope : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        const bool converged = std::abs(next - t) < kLogTolerance;
        t = next;
        if (converged) break;
    }
    return std::exp(t);
}

// The render flattened by its shading, pixel by pixel: r / h, scaled so
// that its mean display level is the render's (the flattened image is the
// stone at the render's brightness A). Both renders follow the same paths
// (common random numbers, one majorant), so the noise they share cancels in
// the ratio; pixels whose shading is below 5 % of its mean (the dark rim)
// are left out.
ObjectChannel flattened(const ObjectChannel& r, const ObjectChannel& h) {
    ObjectChannel f = r;
    double h_mean = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < r.inside.size(); ++i)
        if (r.inside[i] && h.inside[i]) h_mean += h.value[i], ++n;
    h_mean = n ? h_mean / double(n) : 0.0;
    for (std::size_t i = 0; i < r.inside.size(); ++i) {
        f.inside[i] = r.inside[i] && h.inside[i] && h_mean > 0.0 && h.value[i] >= 0.05 * h_mean;
        f.value[i] = f.inside[i] ? r.value[i] / h.value[i] : 0.0;
    }
    ObjectChannel r_inside = r;
    r_inside.inside = f.inside;
    const double scale = scale_to_mean_level(f, mean_level(r_inside, 1.0));
    for (double& v : f.value) v *= scale;
    return f;
}

// The spread of the levels of a channel's object pixels.
double level_spread(const ObjectChannel& f) {
    double sum = 0.0, sum2 = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < f.inside.size(); ++i) {
        if (!f.inside[i]) continue;
        const double level = continuous_level(f.value[i]);
        sum += level;
        sum2 += level * level;
        ++n;
    }
    if (n < 2) return 0.0;
    const double mean = sum / double(n);
    return std::sqrt(std::max(0.0, sum2 / double(n) - mean * mean));
}

// The covariance of two images' levels over the blocks inside both: the
// variance of what they share (when their noise is independent).
double level_covariance(const ObjectChannel& a, const ObjectChannel& b) {
    double sum_a = 0.0, sum_b = 0.0, sum_ab = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.inside.size(); ++i) {
        if (!a.inside[i] || !b.inside[i]) continue;
        const double la = continuous_level(a.value[i]), lb = continuous_level(b.value[i]);
        sum_a += la;
        sum_b += lb;
        sum_ab += la * lb;
        ++n;
    }
    if (n < 2) return 0.0;
    return sum_ab / double(n) - (sum_a / double(n)) * (sum_b / double(n));
}

// Channel c of a render flattened by its shading render, in blocks.
ObjectChannel flat_blocks(const ImageF32& render, const ImageF32& shading, int c, float exposure, int block) {
    return block_means(flattened(object_channel(render, c, exposure), object_channel(shading, c, exposure)), block);
}

// The covariances of the flattened blocks' levels between every pair of
// independent pieces: each an estimate of the variance of the image those
// pieces share.
std::vector<double> pair_covariances(const std::vector<ImageF32>& render, const std::vector<ImageF32>& shading,
                                     int c, float exposure, int block) {
    // Each piece flattened on its own (tasks alike whatever the thread
    // count: the same sums in the same order, the same result).
    std::vector<ObjectChannel> flat(render.size());
    tbb::parallel_for(std::size_t(0), render.size(),
                      [&](std::size_t i) { flat[i] = flat_blocks(render[i], shading[i], c, exposure, block); });
    std::vector<double> out;
    for (std::size_t i = 0; i < flat.size(); ++i)
        for (std::size_t j = i + 1; j < flat.size(); ++j) out.push_back(level_covariance(flat[i], flat[j]));
    return out;
}

double mean_of(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); }

// The sample standard deviation of a few values.
double scatter_of(const std::vector<double>& v) {
    if (v.size() < 2) return 0.0;
    const double m = mean_of(v);
    double sum2 = 0.0;
    for (double x : v) sum2 += (x - m) * (x - m);
    return std::sqrt(sum2 / double(v.size() - 1));
}

}  // namespace

int material_block(double relative_error) {
    constexpr double kBlockError = 0.1;
    return std::clamp(int(std::ceil(relative_error / kBlockError)), 1, kMaxMaterialBlock);
}

MaterialSpread material_spread(const SplitFilms& render, const SplitFilms& shading, float exposure, int block) {
    if (render.first.width() != shading.first.width() || render.first.height() != shading.first.height() ||
        render.quarters.size() != shading.quarters.size())
        throw Error("internal: material_spread needs a render and a shading render of one size and split");
    const std::vector<ImageF32> halves{film_image(render.first), film_image(render.second)},
        shading_halves{film_image(shading.first), film_image(shading.second)};
    const ImageF32 whole = film_image(render.merged()), whole_shading = film_image(shading.merged());
    MaterialSpread m;
    // The channels apart, in parallel: 21 images flattened, each a
    // bisection of 35 passes with an sRGB encoding per pixel (seconds on one
    // core at 512², a wait at every contrast step).
    tbb::parallel_for(0, 3, [&](int c) {
        double variance = mean_of(pair_covariances(halves, shading_halves, c, exposure, block));
        // Richardson: the bias falls as 1/n, so V(∞) ≈ 2·V(n/2) − V(n/4).
        if (!render.quarters.empty()) {
            const std::vector<double> quarters =
                pair_covariances(render.quarters, shading.quarters, c, exposure, block);
            variance = 2.0 * variance - mean_of(quarters);
            m.scatter[c] = scatter_of(quarters);
        }
        const double spread = level_spread(flat_blocks(whole, whole_shading, c, exposure, block));
        m.s[c] = std::sqrt(std::max(0.0, variance));
        m.noise[c] = std::sqrt(std::max(0.0, spread * spread - m.s[c] * m.s[c]));
    });
    return m;
}

Photo flat_render(const Film& render, const Film& shading, float exposure, int block) {
    if (render.width() != shading.width() || render.height() != shading.height())
        throw Error("internal: flat_render needs a render and a shading render of one size");
    Photo p;
    p.width = render.width() / block;
    p.height = render.height() / block;
    const std::size_t n = std::size_t(p.width) * p.height;
    p.levels.assign(n, Rgb8{0, 0, 0});
    p.foreground.assign(n, 1);
    const ImageF32 r = film_image(render), h = film_image(shading);
    for (int c = 0; c < 3; ++c) {
        const ObjectChannel f = flat_blocks(r, h, c, exposure, block);
        for (std::size_t i = 0; i < n; ++i) {
            p.levels[i][c] = display_level(f.value[i]);
            p.foreground[i] = p.foreground[i] && f.inside[i];
        }
    }
    return p;
}

namespace {

// The photo's linear colour over each render pixel's footprint: the photo
// laid flat from the image's corner, `scale` photo pixels to a render pixel,
// repeated, box-averaged with each photo pixel weighed by the share of it
// the footprint covers, over the photo's foreground. A footprint mostly of
// background is not inside.
struct StoneImage {
    std::vector<std::array<double, 3>> linear;
    std::vector<std::uint8_t> inside;
};

// Photo pixels [a, b) of a repeating row of n: (pixel modulo n, share).
std::vector<std::pair<int, double>> footprint(double a, double b, int n) {
    std::vector<std::pair<int, double>> out;
    for (long j = long(std::floor(a)); double(j) < b; ++j) {
        const double w = std::min(b, double(j + 1)) - std::max(a, double(j));
        if (w > 0.0) out.emplace_back(int(((j % n) + n) % n), w);
    }
    return out;
}

StoneImage stone_at_render_scale(const Photo& photo, int width, int height, double scale) {
    std::vector<std::array<double, 3>> lin(photo.levels.size());
    for (std::size_t i = 0; i < lin.size(); ++i)
        for (int c = 0; c < 3; ++c) lin[i][c] = srgb_decode(photo.levels[i][c] / 255.0);
    std::vector<std::vector<std::pair<int, double>>> columns(static_cast<std::size_t>(width));
    for (int x = 0; x < width; ++x) columns[std::size_t(x)] = footprint(x * scale, (x + 1) * scale, photo.width);
    StoneImage s;
    s.linear.assign(std::size_t(width) * height, {0.0, 0.0, 0.0});
    s.inside.assign(s.linear.size(), 0);
    for (int y = 0; y < height; ++y) {
        const auto rows = footprint(y * scale, (y + 1) * scale, photo.height);
        for (int x = 0; x < width; ++x) {
            std::array<double, 3> sum{0.0, 0.0, 0.0};
            double covered = 0.0, all = 0.0;
            for (const auto& [py, wy] : rows)
                for (const auto& [px, wx] : columns[std::size_t(x)]) {
                    const std::size_t j = std::size_t(py) * photo.width + std::size_t(px);
                    all += wx * wy;
                    if (!photo.foreground[j]) continue;
                    covered += wx * wy;
                    for (int c = 0; c < 3; ++c) sum[c] += wx * wy * lin[j][c];
                }
            if (!(2.0 * covered >= all) || !(covered > 0.0)) continue;
            const std::size_t i = std::size_t(y) * width + x;
            for (int c = 0; c < 3; ++c) s.linear[i][c] = sum[c] / covered;
            s.inside[i] = 1;
        }
    }
    return s;
}

}  // namespace

Photo shaded_photo(const Photo& photo, const Film& shading, float exposure, double render_pixels_per_side) {
    const StoneImage stone = stone_at_render_scale(photo, shading.width(), shading.height(),
                                                   photo_pixels_per_side(photo) / render_pixels_per_side);
    const ImageF32 h = film_image(shading);
    Photo out;
    out.width = shading.width();
    out.height = shading.height();
    out.levels.assign(std::size_t(out.width) * out.height, Rgb8{0, 0, 0});
    out.foreground.assign(out.levels.size(), 0);
    const RgbHistogram photo_levels = RgbHistogram::of(photo.foreground_levels());
    for (int c = 0; c < 3; ++c) {
        ObjectChannel f = object_channel(h, c, exposure);
        for (std::size_t i = 0; i < f.value.size(); ++i) {
            f.inside[i] = f.inside[i] && stone.inside[i];
            f.value[i] *= stone.linear[i][c];
        }
        const double scale = scale_to_mean_level(f, photo_levels.mean(c));
        for (std::size_t i = 0; i < f.value.size(); ++i) {
            out.levels[i][c] = display_level(scale * f.value[i]);
            out.foreground[i] = c == 0 ? f.inside[i] : out.foreground[i] && f.inside[i];
        }
    }
    return out;
}

namespace {

// The histogram of display_level(a · v) over the sorted values v, as
// proportions: level l takes the values with a·v below the upper edge of l's
// rounding interval and not below l − 1's.
std::vector<double> scaled_histogram(const std::vector<double>& sorted, double a) {
    std::vector<double> h(256, 0.0);
    std::size_t below = 0;
    for (int l = 0; l < 255; ++l) {
        const double edge = srgb_decode((l + 0.5) / 255.0) / a;
        const std::size_t upto = std::size_t(std::lower_bound(sorted.begin(), sorted.end(), edge) - sorted.begin());
        h[std::size_t(l)] = double(upto - below);
        below = upto;
    }
    h[255] = double(sorted.size() - below);
    for (double& x : h) x /= double(sorted.size());
    return h;
}

}  // namespace

namespace {

// The mixture's components under a shading: the histograms of a·v over a
// log grid of multipliers a about 1 % apart, `v` the shading's object
// values, sorted, and their mean levels, the mixture's mean held at the
// photo's A, `photo_mean` (or the nearest A any multiplier reaches).
struct MaterialColumns {
    std::vector<std::vector<double>> histograms;
    std::vector<double> multipliers;  // a, one per histogram (with a mean)
    MixtureMean mean;
};
MaterialColumns material_columns(const std::vector<double>& v, double photo_mean) {
    MaterialColumns out;
    const auto positive = std::upper_bound(v.begin(), v.end(), 0.0);
    // No light: every material shows black.
    if (positive == v.end()) {
        out.histograms.push_back(scaled_histogram(v, 1.0));
        return out;
    }
    // From every pixel at level 0 to every lit pixel at 255; beyond either
    // end the histogram no longer changes.
    const double lo = srgb_decode(0.5 / 255.0) / v.back(), hi = srgb_decode(254.5 / 255.0) / *positive;
    constexpr double kStep = 0.01;
    constexpr int kMostColumns = 2048;
    const int n = std::clamp(int(std::ceil(std::log(hi / lo) / std::log1p(kStep))) + 1, 2, kMostColumns);
    for (int j = 0; j < n; ++j) {
        out.multipliers.push_back(lo * std::pow(hi / lo, double(j) / double(n - 1)));
        out.histograms.push_back(scaled_histogram(v, out.multipliers.back()));
        double m = 0.0;
        for (int l = 0; l < 256; ++l) m += l * out.histograms.back()[std::size_t(l)];
        out.mean.column_means.push_back(m);
    }
    // The render's A is the photo's, as the fit makes it; where unlit
    // pixels keep every material below it, the nearest A one reaches.
    const auto [least, most] = std::minmax_element(out.mean.column_means.begin(), out.mean.column_means.end());
    out.mean.mean = std::clamp(photo_mean, *least, *most);
    return out;
}

// To 10⁻⁵ at least: D is reported to 10⁻⁴ (the demo's blue, D about 6·10⁻⁵,
// took 7660 iterations to 10⁻⁶ and 600 to 10⁻⁵).
constexpr double kLeastRelativeGap = 1e-2, kLeastAbsoluteGap = 1e-5;

// The histogram of one level `m`, fractional, its mass split between the
// two levels either side.
std::vector<double> level_histogram(double m) {
    std::vector<double> h(256, 0.0);
    const double x = std::clamp(m, 0.0, 255.0);
    const int l = std::min(254, int(x));
    h[std::size_t(l)] = double(l + 1) - x;
    h[std::size_t(l) + 1] = x - double(l);
    return h;
}

// Each column's material as the flattened render shows it (render over
// shading, scaled to the render's A): one level, the material's multiplier
// against the multiplier a* whose render alone has the mixture's mean A,
// which the flattening shows at A: level(a / a* · linear(A)). Fixed per
// column, so a ceiling on the distance of their histogram keeps the problem
// convex. (The mean level a column shows over the object is another
// measure: there the shading's highlights clip at 255 and its shadows
// crowd the sRGB curve's steep end. The two gave the same bound to 10⁻⁴ on
// the demo's vase and bunny and on Marble01's vase.)
std::vector<double> flattened_levels(const MaterialColumns& c) {
    const std::vector<double>& m = c.mean.column_means;
    // The column means rise with a; a* by log-interpolation between the
    // two about A.
    const auto above = std::lower_bound(m.begin(), m.end(), c.mean.mean);
    const std::size_t j = std::size_t(std::clamp<std::ptrdiff_t>(above - m.begin(), 1, std::ptrdiff_t(m.size()) - 1));
    const double t = m[j] > m[j - 1] ? std::clamp((c.mean.mean - m[j - 1]) / (m[j] - m[j - 1]), 0.0, 1.0) : 0.0;
    const double a_star = c.multipliers[j - 1] * std::pow(c.multipliers[j] / c.multipliers[j - 1], t);
    const double linear_a = srgb_decode(c.mean.mean / 255.0);
    std::vector<double> levels;
    for (double a : c.multipliers) levels.push_back(continuous_level(a / a_star * linear_a));
    return levels;
}

// One channel of least_material_distance: `v` the shading's object values,
// sorted; `target` the photo's histogram and `photo_mean` its A. With
// `material_most` ≥ 0, of the materials whose own histogram of levels, as the
// flattened render shows them (flattened_levels), is within that D of
// `material_target`.
double least_channel_distance(const std::vector<double>& v, const std::vector<double>& target, double photo_mean,
                              double material_most, const std::vector<double>& material_target) {
    const MaterialColumns c = material_columns(v, photo_mean);
    if (c.mean.column_means.empty()) return simplex_least_squares(c.histograms, target).value;
    if (material_most < 0.0)
        return simplex_least_squares(c.histograms, target, c.mean, kLeastRelativeGap, kLeastAbsoluteGap).lower_bound;
    MixtureNear near;
    near.target = material_target;
    near.most = material_most;
    for (double level : flattened_levels(c)) near.columns.push_back(level_histogram(level));
    return simplex_least_squares_near(c.histograms, target, near, c.mean, kLeastRelativeGap, kLeastAbsoluteGap)
        .lower_bound;
}

// least_channel_distance for each channel, in parallel (a second or a few each).
std::array<double, 3> least_distances(const Photo& photo, const Film& shading, float exposure,
                                      const std::array<double, 3>& material_most,
                                      const RgbHistogram& material_photo) {
    std::array<double, 3> out{-1.0, -1.0, -1.0};
    const RgbHistogram photo_levels = RgbHistogram::of(photo.foreground_levels());
    if (!photo_levels.total) return out;
    const ImageF32 image = film_image(shading);
    tbb::parallel_for(0, 3, [&](int c) {
        const ObjectChannel f = object_channel(image, c, exposure);
        std::vector<double> v;
        for (std::size_t i = 0; i < f.value.size(); ++i)
            if (f.inside[i]) v.push_back(std::max(f.value[i], 0.0));
        if (v.empty()) return;
        std::sort(v.begin(), v.end());
        std::vector<double> target(256);
        for (int l = 0; l < 256; ++l) target[std::size_t(l)] = photo_levels.proportion(c, l);
        const double most = material_most[std::size_t(c)];
        std::vector<double> material_target;
        if (most >= 0.0)
            for (int l = 0; l < 256; ++l) material_target.push_back(material_photo.proportion(c, l));
        out[std::size_t(c)] = least_channel_distance(v, target, photo_levels.mean(c), most, material_target);
    });
    return out;
}

}  // namespace

std::array<double, 3> least_material_distance(const Photo& photo, const Film& shading, float exposure) {
    return least_distances(photo, shading, exposure, {-1.0, -1.0, -1.0}, {});
}

std::array<double, 3> least_material_distance_as_near(const Photo& photo, const Film& shading, float exposure,
                                                      const std::array<double, 3>& material_d,
                                                      const RgbHistogram& material_photo) {
    // Without the photo's histogram or a material D there is nothing to
    // hold the material near.
    if (!material_photo.total) return {-1.0, -1.0, -1.0};
    std::array<double, 3> out = least_distances(photo, shading, exposure, material_d, material_photo);
    for (int c = 0; c < 3; ++c)
        if (!(material_d[std::size_t(c)] >= 0.0)) out[std::size_t(c)] = -1.0;
    return out;
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
