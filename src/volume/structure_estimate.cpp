#include "jade/volume/structure_estimate.h"

#include "jade/core/display.h"
#include "jade/core/error.h"
#include "jade/core/timing.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <tuple>

namespace jade {

StructureMode parse_structure_mode(const std::string& s) {
    if (s == "fbm") return StructureMode::Fbm;
    if (s == "photo") return StructureMode::Photo;
    if (s == "exemplar") return StructureMode::Exemplar;
    throw Error(std::string("--structure must be ") + structure_mode_names() + ", got '" + s + "'");
}

const char* structure_mode_names() { return "'photo', 'exemplar' or 'fbm'"; }

const char* to_string(StructureMode m) {
    switch (m) {
    case StructureMode::Fbm: return "fbm";
    case StructureMode::Photo: return "photo";
    case StructureMode::Exemplar: return "exemplar";
    }
    return "?";
}

GrayImage photo_luma(const Photo& photo) {
    GrayImage g;
    g.width = photo.width;
    g.height = photo.height;
    g.values.resize(photo.levels.size());
    for (std::size_t i = 0; i < photo.levels.size(); ++i)
        g.values[i] = float(luma(photo.levels[i][0], photo.levels[i][1], photo.levels[i][2]));
    g.mask = photo.foreground;
    return g;
}

double photo_extent_pixels(const Photo& photo) {
    const std::array<int, 4> box = photo.foreground_box();
    return double(std::max(box[2], box[3]));
}

double photo_pixels_per_side(const Photo& photo) { return photo_extent_pixels(photo) / photo.span; }

GrayImage matched_noise_slice(const NoiseParams& noise, int z, const std::vector<float>& sorted_luma) {
    const int s = noise.resolution;
    std::vector<float> values(std::size_t(s) * s);
    fbm_slice(Fbm(noise), s, z, values.data());
    // Rank matching: the i-th smallest noise value takes the photo's luma of
    // the same quantile, as colour matching does (§4.2). The ranks come from
    // one sort of (value, pixel) keys, a value's bits made to order as the
    // value does: a third of the time of a sort through the values.
    std::vector<std::uint64_t> order(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, &values[i], sizeof bits);
        bits = (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
        order[i] = (std::uint64_t(bits) << 32) | std::uint64_t(i);
    }
    std::sort(order.begin(), order.end());
    GrayImage g;
    g.width = g.height = s;
    g.values.resize(values.size());
    const double scale = double(sorted_luma.size()) / double(values.size());
    for (std::size_t r = 0; r < order.size(); ++r) {
        const std::uint32_t i = std::uint32_t(order[r]);
        const int x = int(i % s), y = int(i / s);
        // Seen from +z with y up: row 0 shows the largest y.
        g.values[std::size_t(s - 1 - y) * s + x] = sorted_luma[std::size_t((r + 0.5) * scale)];
    }
    return g;
}

namespace {

// Candidate slices are generated at this resolution at most: the spectrum
// bands beyond its Nyquist frequency (128 cycles per side) are fine grain
// that multiple scattering averages away in a render.
constexpr int kEstimateResolution = 256;

struct PhotoTexture {
    TextureSpectrum spectrum;
    std::vector<float> sorted_luma;
};

// In the photo's own frame (it spans one side): the search's grids and the
// candidates' slices are the photo's scale whatever its span.
PhotoTexture photo_texture(const Photo& photo) {
    const GrayImage g = photo_luma(photo);
    PhotoTexture t{texture_spectrum(g, photo_extent_pixels(photo)), {}};
    for (std::size_t i = 0; i < g.values.size(); ++i)
        if (g.inside(int(i % g.width), int(i / g.width))) t.sorted_luma.push_back(g.values[i]);
    std::sort(t.sorted_luma.begin(), t.sorted_luma.end());
    return t;
}

// Two slices a quarter and three quarters deep, so that one slice's chance
// pattern does not decide: the spectra of slice(depth) at each, made in
// parallel, and their measures against the photo's averaged in their order.
StructureFit measure_two_slices(int resolution, const TextureSpectrum& photo,
                                const std::function<GrayImage(int depth)>& slice) {
    const int depths[2] = {resolution / 4, 3 * resolution / 4};
    TextureSpectrum spectra[2];
    tbb::parallel_for(0, 2, [&](int i) { spectra[i] = texture_spectrum(slice(depths[i]), double(resolution)); });
    StructureFit fit;
    for (const TextureSpectrum& sp : spectra) {
        fit.distance += 0.5 * structure_distance(sp, photo);
        fit.strength += 0.5 * sp.strength;
        fit.coherence += 0.5 * sp.coherence;
        fit.defects += 0.5 * sp.defects;
        fit.orientation = sp.orientation;
    }
    return fit;
}

StructureFit evaluate(const NoiseParams& noise, const PhotoTexture& photo) {
    NoiseParams at = noise;
    at.resolution = std::min(noise.resolution, kEstimateResolution);
    StructureFit fit = measure_two_slices(at.resolution, photo.spectrum, [&](int depth) {
        return matched_noise_slice(at, depth, photo.sorted_luma);
    });
    fit.noise = noise;
    return fit;
}

// Every parameter a slice depends on, as one ordered key.
auto noise_key(const NoiseParams& p) {
    return std::make_tuple(p.resolution, p.octaves, p.k, p.seed, p.frequency, p.stretch, p.angle, p.bands, p.warp,
                           p.veins, p.vein_frequency, p.vein_width, p.layers, p.fold);
}

// The evaluations of one estimate, each made once: coordinate descent meets
// the same parameters again (every sweep holds the point it starts from, the
// last round repeats the one before where nothing moved, and the three
// starts' paths cross), a quarter to a third of the evaluations on the
// photos measured (docs/design.md, "Structure").
class Evaluations {
public:
    explicit Evaluations(const PhotoTexture& texture) : texture_(texture) {}
    const PhotoTexture& texture() const { return texture_; }
    // The fits of `candidates`, in their order; those not seen before are
    // evaluated in parallel.
    std::vector<StructureFit> of(const std::vector<NoiseParams>& candidates) {
        std::vector<NoiseParams> missing;
        for (const NoiseParams& p : candidates)
            if (!seen_.count(noise_key(p)) &&
                std::none_of(missing.begin(), missing.end(),
                             [&](const NoiseParams& m) { return noise_key(m) == noise_key(p); }))
                missing.push_back(p);
        std::vector<StructureFit> fits(missing.size());
        tbb::parallel_for(std::size_t(0), missing.size(),
                          [&](std::size_t i) { fits[i] = evaluate(missing[i], texture_); });
        for (const StructureFit& f : fits) seen_.emplace(noise_key(f.noise), f);
        std::vector<StructureFit> out;
        for (const NoiseParams& p : candidates) out.push_back(seen_.at(noise_key(p)));
        return out;
    }
    StructureFit of(const NoiseParams& p) { return of(std::vector<NoiseParams>{p}).front(); }
    int count() const { return int(seen_.size()); }

private:
    const PhotoTexture& texture_;
    std::map<decltype(noise_key(NoiseParams{})), StructureFit> seen_;
};

// What the search minimises: the spectra's distance and the differences in
// how strongly oriented the two are, globally and locally (the radial
// spectrum sees neither: a vein and grain of the same scale have one
// spectrum); then, with `Measures::WithDefects`, also how far apart their
// orientation defects are, in decades like the spectra's distance, which
// long folded layers and the rings of overturned folds have in very
// different numbers where the other measures hardly differ (docs/design.md,
// "Folds and their defects").
enum class Measures { Spectral, WithDefects };
double objective(const StructureFit& f, const TextureSpectrum& photo, Measures measures) {
    const double spectral =
        f.distance + std::abs(f.strength - photo.strength) + std::abs(f.coherence - photo.coherence);
    if (measures == Measures::Spectral) return spectral;
    // Nine cells of the 30 × 30 between blocks a 32nd of a side wide: fewer
    // defects than that differ by chance (a count of nine is uncertain by a
    // third), and their ratio would make the search's landscape rugged.
    constexpr double kDefectsFloor = 0.01;
    // The count tells structures apart by their topology, by factors of
    // several (the demo photo's folds against its ringed estimate: 4.8);
    // within a factor of √2 it moves with the grain's detail (an fBm's k)
    // and is not counted, so it does not tip families that agree on it.
    const double kDefectsTolerance = 0.5 * std::log10(2.0);
    const double decades =
        std::abs(std::log10(std::max(f.defects, kDefectsFloor) / std::max(photo.defects, kDefectsFloor)));
    return spectral + std::max(0.0, decades - kDefectsTolerance);
}

// The grids the search moves on.
const std::vector<double> kWarps{0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 1, 1.4, 2, 2.8, 4};
const std::vector<double> kFolds{0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 1};

// Coordinate descent from `start` on the spectral measures: each parameter
// over its grid, the others held, until a round changes nothing; every
// parameter but the fold. One parameter's candidates run in parallel.
StructureFit descend(const NoiseParams& start, Evaluations& evaluations) {
    const PhotoTexture& texture = evaluations.texture();
    static const std::vector<double> frequencies{0.5, 0.71, 1, 1.41, 2, 2.83, 4, 5.66, 8};
    static const std::vector<double> ratios{0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85};
    static const std::vector<double> stretches{1, 1.41, 2, 2.83, 4, 5.66, 8, 11.3, 16};
    static const std::vector<double> bands{0, 1, 1.5, 2, 3, 4, 6, 8, 12, 16, 24};
    static const std::vector<double> vein_frequencies{1, 1.41, 2, 2.83, 4, 5.66};
    static const std::vector<double> vein_widths{0.0025, 0.005, 0.01, 0.02};
    StructureFit best = evaluations.of(start);
    auto sweep = [&](const std::vector<double>& grid, double NoiseParams::*field) {
        std::vector<NoiseParams> candidates;
        for (double value : grid) {
            NoiseParams p = best.noise;
            p.*field = value;
            // Layers need bands: the family stays what it started as.
            if (!(p.layers && !(p.bands > 0.0))) candidates.push_back(p);
        }
        bool changed = false;
        for (const StructureFit& f : evaluations.of(candidates))
            if (objective(f, texture.spectrum, Measures::Spectral) <
                objective(best, texture.spectrum, Measures::Spectral) - 1e-9) {
                best = f;
                changed = true;
            }
        return changed;
    };
    for (int round = 0; round < 4; ++round) {
        bool changed = sweep(frequencies, &NoiseParams::frequency);
        changed = sweep(ratios, &NoiseParams::k) || changed;
        changed = sweep(stretches, &NoiseParams::stretch) || changed;
        changed = sweep(bands, &NoiseParams::bands) || changed;
        if (best.noise.bands > 0.0) changed = sweep(kWarps, &NoiseParams::warp) || changed;
        if (best.noise.veins) {
            changed = sweep(vein_frequencies, &NoiseParams::vein_frequency) || changed;
            changed = sweep(vein_widths, &NoiseParams::vein_width) || changed;
        }
        if (!changed) break;
    }
    return best;
}

// How the bands of `fit` fold: the fold and the warp over their whole grid
// (88 pairs, in parallel), on every measure with the defects, the rest held.
// The defects are there to choose how the layers fold; over every parameter
// their ratio would wall a start into the first basin whose count happens to
// match, or tip between families the spectral measures rank. Both at once,
// because whether a fold overturns depends on their product: one at a time,
// the search stopped on Onyx010 at ε = 0.7 with a few closed loops, where
// ε = 0.05 with a warp one step stronger has none and scores as well
// (docs/design.md, "The fold and the warp together").
StructureFit fold_layers(const StructureFit& fit, Evaluations& evaluations) {
    if (!(fit.noise.bands > 0.0)) return fit;
    std::vector<NoiseParams> candidates;
    for (double fold : kFolds)
        for (double warp : kWarps) {
            NoiseParams p = fit.noise;
            p.fold = fold, p.warp = warp;
            candidates.push_back(p);
        }
    const TextureSpectrum& photo = evaluations.texture().spectrum;
    StructureFit best = fit;
    for (const StructureFit& f : evaluations.of(candidates))
        if (objective(f, photo, Measures::WithDefects) < objective(best, photo, Measures::WithDefects) - 1e-9)
            best = f;
    return best;
}

}  // namespace

StructureFit evaluate_structure(const NoiseParams& noise, const Photo& photo) {
    StructureFit f = evaluate(magnified(noise, 1.0 / photo.span), photo_texture(photo));
    f.noise = noise;
    return f;
}

namespace {

// The luma of a built volume's slice normal to `axis` (0 x, 1 y, 2 z) at
// `depth`: normal to z seen from +z with y up, as matched_noise_slice shows
// a slice; normal to x seen from +x with y up (z to the left); normal to y
// seen from +y, x to the right and z down.
GrayImage volume_slice_luma(const std::vector<Rgb8>& levels, int s, int axis, int depth) {
    GrayImage g;
    g.width = g.height = s;
    g.values.resize(std::size_t(s) * s);
    for (int row = 0; row < s; ++row)
        for (int col = 0; col < s; ++col) {
            int x = col, y = s - 1 - row, z = depth;
            if (axis == 0) x = depth, z = s - 1 - col;
            if (axis == 1) y = depth, z = row;
            const Rgb8& v = levels[(std::size_t(z) * s + y) * s + x];
            g.values[std::size_t(row) * s + col] = float(luma(v[0], v[1], v[2]));
        }
    return g;
}

}  // namespace

StructureFit measure_slice_structure(const std::vector<Rgb8>& levels, int resolution, const Photo& photo) {
    const TextureSpectrum target = texture_spectrum(photo_luma(photo), photo_pixels_per_side(photo));
    return measure_two_slices(resolution, target,
                              [&](int depth) { return volume_slice_luma(levels, resolution, 2, depth); });
}

StructureFit measure_slice_structure_across(const std::vector<Rgb8>& levels, int resolution, const Photo& photo) {
    const TextureSpectrum target = texture_spectrum(photo_luma(photo), photo_pixels_per_side(photo));
    StructureFit fit;
    for (int axis : {0, 1}) {
        const StructureFit one = measure_two_slices(
            resolution, target, [&](int depth) { return volume_slice_luma(levels, resolution, axis, depth); });
        fit.distance += 0.5 * one.distance;
        fit.strength += 0.5 * one.strength;
        fit.coherence += 0.5 * one.coherence;
        fit.defects += 0.5 * one.defects;
    }
    return fit;
}

StructureEstimate estimate_structure(const Photo& photo, const NoiseParams& base) {
    const Stopwatch clock;
    const PhotoTexture texture = photo_texture(photo);
    Evaluations evaluations(texture);
    StructureEstimate out;
    out.photo = texture.spectrum;
    out.photo_span = photo.span;
    // The search runs in the photo's frame and its outcome is magnified by
    // the photo's span into the cube's (docs/design.md, "The photo's span");
    // the paper's fBm, one cycle per cube side, is span cycles per photo.
    NoiseParams paper = base;
    paper.frequency = 1.0, paper.stretch = 1.0, paper.angle = 0.0, paper.bands = 0.0, paper.veins = false;
    paper.layers = false;
    out.paper = evaluations.of(magnified(paper, 1.0 / photo.span));
    out.paper.noise = paper;
    // A photo with no measured power in any band (one colour) has no
    // structure to match: every candidate's distance to it is undefined,
    // and the search would evaluate hundreds of candidates (287 at 64³; 17 s
    // at the default 256³ on 2 cores) to keep the paper's fBm.
    if (std::none_of(texture.spectrum.power.begin(), texture.spectrum.power.end(), [](double p) { return p > 0.0; })) {
        out.chosen = out.paper;
        out.seconds = clock.seconds();
        out.evaluations = evaluations.count();
        return out;
    }

    // Three starts, the paper's fBm, a marble and folded layers, because the
    // families' optima are far apart and coordinate descent would not cross
    // between them (the layers stay layers: they need bands).
    // Asked for veins (base.veins), every start has them and the descent
    // searches their frequency and width too: the measures below do not
    // choose veins by themselves (docs/design.md, "Structure").
    NoiseParams fbm = base;
    fbm.frequency = 1.0, fbm.stretch = 1.0, fbm.angle = 0.0, fbm.bands = 0.0, fbm.layers = false;
    fbm.veins = base.veins;  // with base's vein frequency and width as the descent's start
    NoiseParams marble = fbm;
    marble.bands = 8.0, marble.warp = 1.0, marble.frequency = 2.0;
    NoiseParams layered = fbm;
    layered.layers = true, layered.bands = 2.0, layered.warp = 1.0, layered.k = 0.85;
    StructureFit best_fit = evaluations.of(fbm);
    // Each start descends on the spectral measures, then folds its layers
    // with the defects too; the starts are compared on all the measures.
    for (NoiseParams start : {fbm, marble, layered}) {
        start.angle = texture.spectrum.orientation;
        const StructureFit fit = fold_layers(descend(start, evaluations), evaluations);
        if (objective(fit, texture.spectrum, Measures::WithDefects) <
            objective(best_fit, texture.spectrum, Measures::WithDefects))
            best_fit = fit;
    }
    out.chosen = best_fit;
    out.chosen.noise = magnified(best_fit.noise, photo.span);
    out.seconds = clock.seconds();
    out.evaluations = evaluations.count();
    return out;
}

NoiseParams choose_noise(const Photo& photo, const NoiseParams& given, StructureMode mode,
                         StructureEstimate* estimate) {
    given.validate();
    if (mode == StructureMode::Fbm) return given;
    if (mode == StructureMode::Exemplar) {
        NoiseParams noise = given;
        noise.exemplar = true;
        return noise;
    }
    StructureEstimate e = estimate_structure(photo, given);
    if (estimate) *estimate = e;
    return e.chosen.noise;
}

}  // namespace jade
