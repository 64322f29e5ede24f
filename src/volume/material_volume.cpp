#include "jade/volume/material_volume.h"

#include "jade/volume/exemplar.h"
#include "jade/volume/sharpen.h"

#include "jade/core/error.h"
#include "jade/core/progress.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>

namespace jade {

void OpticalParams::validate() const {
    if (!(ds > 0.0) || !std::isfinite(ds))
        throw Error("--ds must be a positive number, got " + std::to_string(ds));
    if (!(da >= 0.0) || !std::isfinite(da))
        throw Error("--da must be zero or positive, got " + std::to_string(da));
    for (double k : ks)
        if (!std::isfinite(k)) throw Error("--ks must be finite numbers");
    for (double g : contrast)
        if (!(g >= 0.0 && g <= kMaxContrast))
            throw Error("--contrast must be between 0 and " + std::to_string(int(kMaxContrast)) + " in every channel");
    for (double m : mean_level)
        if (!(m >= 0.0 && m <= 1.0)) throw Error("the volume's mean level must lie in [0, 1]");
    if (!(density_scale > 0.0) || !std::isfinite(density_scale))
        throw Error("--density-scale must be a positive number, got " +
                    std::to_string(density_scale));
}

double contrasted_level(int level, int channel, const OpticalParams& p) {
    const double vc = level / 256.0;
    const double g = p.contrast[channel];
    if (g == 1.0) return vc;  // exactly the paper's level
    const double m = p.mean_level[channel];
    return std::clamp(m + g * (vc - m), 0.0, 1.0);
}

const char* to_string(Extinction extinction) { return extinction == Extinction::Grey ? "grey" : "paper"; }

Extinction parse_extinction(const std::string& text) {
    if (text == "grey") return Extinction::Grey;
    if (text == "paper") return Extinction::Paper;
    throw Error("--extinction must be 'grey' or 'paper', got '" + text + "'");
}

namespace {

// §5.1's coefficients of a level, before the extinction is chosen.
struct PaperPair {
    double s, a;
};
PaperPair section_5_1(int level, int channel, const OpticalParams& p) {
    const double v = contrasted_level(level, channel, p);
    return {std::max(0.0, v * p.ds + p.ks[channel]), (1.0 - v) * p.ds * p.da};
}

// The share of the extinction d_s that scatters: §5.1's albedo (0 where §5.1
// gives no extinction at all).
double grey_albedo(const PaperPair& c) { return c.s + c.a > 0.0 ? c.s / (c.s + c.a) : 0.0; }

}  // namespace

double paper_sigma_s(int level, int channel, const OpticalParams& p) {
    const PaperPair c = section_5_1(level, channel, p);
    return p.extinction == Extinction::Grey ? p.ds * grey_albedo(c) : c.s;
}

double paper_sigma_a(int level, int channel, const OpticalParams& p) {
    const PaperPair c = section_5_1(level, channel, p);
    return p.extinction == Extinction::Grey ? p.ds * (1.0 - grey_albedo(c)) : c.a;
}

std::array<double, 3> mean_levels(const std::vector<Rgb8>& levels) {
    std::array<double, 3> sum{0, 0, 0};
    for (const Rgb8& lv : levels)
        for (int c = 0; c < 3; ++c) sum[c] += lv[c];
    std::array<double, 3> mean{0.5, 0.5, 0.5};
    if (!levels.empty())
        for (int c = 0; c < 3; ++c) mean[c] = sum[c] / (256.0 * double(levels.size()));
    return mean;
}

LevelHistograms level_histograms(const std::vector<Rgb8>& levels) {
    LevelHistograms h{};
    for (const Rgb8& lv : levels)
        for (int c = 0; c < 3; ++c) h[c][lv[c]] += 1.0;
    return h;
}

double contrasted_spread(const LevelHistograms& histograms, int channel, const OpticalParams& p) {
    double n = 0.0, sum = 0.0, sum2 = 0.0;
    for (int level = 0; level < 256; ++level) {
        const double w = histograms[channel][level], v = contrasted_level(level, channel, p);
        n += w;
        sum += w * v;
        sum2 += w * v * v;
    }
    if (!(n > 0.0)) return 0.0;
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

double contrasted_spread_elasticity(const LevelHistograms& histograms, int channel, const OpticalParams& p) {
    // A central difference over ±1 % of g: the spread is piecewise smooth
    // in g (a level starts to clip at one g), and 1 % spans few such kinks.
    constexpr double kStep = 1.01;
    OpticalParams lo = p, hi = p;
    lo.contrast[channel] = p.contrast[channel] / kStep;
    hi.contrast[channel] = p.contrast[channel] * kStep;
    const double a = contrasted_spread(histograms, channel, lo), b = contrasted_spread(histograms, channel, hi);
    if (!(a > 0.0 && b > 0.0)) return 1.0;
    return std::log(b / a) / (2.0 * std::log(kStep));
}

CoefficientTable::CoefficientTable(const OpticalParams& p, double cube_side) {
    const double to_world = p.density_scale / cube_side;
    for (int c = 0; c < 3; ++c)
        for (int level = 0; level < 256; ++level) {
            sigma_s[c][level] = float(paper_sigma_s(level, c, p) * to_world);
            sigma_a[c][level] = float(paper_sigma_a(level, c, p) * to_world);
        }
}

MeanCoefficients mean_coefficients(const MaterialVolume& volume) {
    // Per channel, a histogram of the levels and the table of what each level
    // means: the mean without a coefficient per voxel.
    std::array<std::array<std::size_t, 256>, 3> count{};
    for (const Rgb8& lv : volume.levels)
        for (int c = 0; c < 3; ++c) ++count[c][lv[c]];
    const CoefficientTable table(volume.optics, volume.cube.side);
    MeanCoefficients mean;
    if (volume.levels.empty()) return mean;
    for (int c = 0; c < 3; ++c) {
        for (int level = 0; level < 256; ++level) {
            mean.sigma_s[c] += double(count[c][level]) * table.sigma_s[c][level];
            mean.sigma_a[c] += double(count[c][level]) * table.sigma_a[c][level];
        }
        mean.sigma_s[c] /= double(volume.levels.size());
        mean.sigma_a[c] /= double(volume.levels.size());
    }
    return mean;
}

RgbImage8 slice_image(const MaterialVolume& v, int z) {
    const int s = v.resolution;
    // One entry per level and channel, so the slice costs a lookup per voxel.
    std::array<std::array<std::uint8_t, 256>, 3> shown{};
    for (int c = 0; c < 3; ++c)
        for (int level = 0; level < 256; ++level)
            shown[c][level] = std::uint8_t(std::min(255L, std::lround(256.0 * contrasted_level(level, c, v.optics))));
    RgbImage8 img;
    img.width = img.height = s;
    img.pixels.resize(std::size_t(s) * s * 3);
    for (int y = 0; y < s; ++y)
        for (int x = 0; x < s; ++x)
            for (int c = 0; c < 3; ++c)
                img.pixels[(std::size_t(y) * s + x) * 3 + c] = shown[c][v.levels[v.index(x, y, z)][c]];
    return img;
}

MaterialVolume build_material_volume(const Photo& photo, const NoiseParams& noise, MatchMode match,
                                     const OpticalParams& optics, Progress* progress) {
    noise.validate();
    optics.validate();
    MaterialVolume vol;
    vol.resolution = noise.resolution;
    vol.noise = noise;
    vol.match = match;
    vol.optics = optics;
    vol.photo = photo.path;
    vol.photo_span = photo.span;

    const int s = noise.resolution;
    const std::size_t m = std::size_t(s) * s;
    const std::vector<Rgb8> table = rank_colour_table(photo.foreground_levels(), m, match);
    vol.levels.resize(m * s);
    // Each slice's values, from the noise or from the photo swept in depth;
    // matched as soon as they exist, so no float cube is ever held.
    std::optional<Fbm> fbm;
    std::optional<Exemplar> exemplar;
    if (noise.exemplar)
        exemplar = make_exemplar(photo, s);
    else
        fbm.emplace(noise);
    tbb::parallel_for(tbb::blocked_range<int>(0, s, 1), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> slice(m);
        for (int k = r.begin(); k < r.end(); ++k) {
            if (exemplar)
                swept_slice(*exemplar, s, k, noise.seed, noise.exemplar_wander, slice.data());
            else
                fbm_slice(*fbm, s, k, slice.data());
            match_slice(slice.data(), m, table, &vol.levels[k * m]);
            if (progress) progress->advance();
        }
    });
    vol.sharpen_clipped = sharpen_levels(vol.levels, s, noise.sharpen, noise.sharpen_radius);
    vol.optics.mean_level = mean_levels(vol.levels);
    return vol;
}

}  // namespace jade
