// The structure estimate recovers the parameters of noise it did not see:
// a "photo" made from a slice of known noise (another seed) is analysed, and
// the estimate must land on the generating parameters' grid neighbourhood.

#include "jade/volume/structure_estimate.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

using namespace jade;

namespace {

// A grey photo showing slice z of `noise`, matched to a ramp of levels.
Photo photo_of(const NoiseParams& noise) {
    std::vector<float> ramp;
    for (int i = 0; i < noise.resolution * noise.resolution; ++i)
        ramp.push_back(40.f + 180.f * float(i) / float(noise.resolution * noise.resolution));
    const GrayImage g = matched_noise_slice(noise, noise.resolution / 2, ramp);
    Photo p;
    p.width = g.width;
    p.height = g.height;
    for (float v : g.values) {
        const auto l = std::uint8_t(std::lround(v));
        p.levels.push_back({l, l, l});
    }
    p.foreground.assign(p.levels.size(), 1);
    return p;
}

// Layers of many thicknesses (k 0.85), `bands` per side across `angle`, folded
// by a warp of `warp` sides at `frequency`, on a 128³ grid.
NoiseParams layered_truth(std::uint32_t seed, double bands, double warp, double frequency, double angle) {
    NoiseParams truth;
    truth.resolution = 128;
    truth.seed = seed;
    truth.layers = true;
    truth.bands = bands;
    truth.warp = warp;
    truth.frequency = frequency;
    truth.k = 0.85;
    truth.angle = angle;
    return truth;
}

// Perlin's marble: 12 bands per side across 100°, warped by half a side, on
// a 128³ grid.
NoiseParams marble_truth() {
    NoiseParams truth;
    truth.resolution = 128;
    truth.seed = 3;
    truth.bands = 12.0;
    truth.warp = 0.5;
    truth.frequency = 2.0;
    truth.k = 0.45;
    truth.angle = 100.0;
    return truth;
}

}  // namespace

TEST_CASE("structure estimate: an oriented fBm's frequency, stretch and angle are recovered", "[structure]") {
    NoiseParams truth;
    truth.resolution = 128;
    truth.seed = 7;
    truth.frequency = 4.0;
    truth.k = 0.5;
    truth.stretch = 4.0;
    truth.angle = 30.0;
    NoiseParams base;
    base.resolution = 128;
    base.seed = 1;  // the estimate never sees the photo's noise
    const Photo photo = photo_of(truth);
    const StructureEstimate e = estimate_structure(photo, base);
    const NoiseParams& got = e.chosen.noise;
    CAPTURE(got.frequency, got.k, got.stretch, got.angle, got.bands, e.chosen.distance, e.paper.distance);
    // Each candidate is evaluated once and its fit kept: the kept fit of
    // the chosen parameters is what evaluating them afresh gives, bit for bit.
    const StructureFit again = evaluate_structure(got, photo);
    REQUIRE(again.distance == e.chosen.distance);
    REQUIRE(again.strength == e.chosen.strength);
    REQUIRE(again.coherence == e.chosen.coherence);
    REQUIRE(e.evaluations > 0);
    REQUIRE(got.bands == 0.0);
    REQUIRE(std::abs(got.angle - truth.angle) < 8.0);
    REQUIRE(got.stretch >= truth.stretch / 2.0);
    REQUIRE(got.stretch <= truth.stretch * 2.0);
    REQUIRE(got.frequency >= truth.frequency / 2.0);
    REQUIRE(got.frequency <= truth.frequency * 2.0);
    // And the estimate is much nearer the photo than the paper's fBm.
    REQUIRE(e.chosen.distance < 0.5 * e.paper.distance);
}

TEST_CASE("structure estimate: a photo spanning two cube sides gives the cube its structure twice as coarse",
          "[structure]") {
    // Marble bands, 12 across the photo, which is taken to show two cube
    // sides (a slab twice as wide as the object): per cube side the truth
    // has 6 bands. A slice of the estimated volume, one side wide, must have
    // the photo's spectrum at the photo's scale on the cube (half its pixels
    // per side); the truth's parameters taken per cube side (the photo's
    // structure at its own scale, twice too fine) must not. (Bands, not a
    // plain fBm: a power law's spectrum looks the same an octave up.)
    const NoiseParams truth = marble_truth();
    NoiseParams base;
    base.resolution = 128;
    Photo photo = photo_of(truth);
    photo.span = 2.0;
    REQUIRE(photo_extent_pixels(photo) == 128.0);
    REQUIRE(photo_pixels_per_side(photo) == 64.0);
    const StructureEstimate e = estimate_structure(photo, base);
    const NoiseParams& got = e.chosen.noise;
    CAPTURE(got.frequency, got.k, got.stretch, got.angle, got.bands, got.warp, got.octaves, e.chosen.distance,
            e.paper.distance);
    CHECK(got.bands >= truth.bands / 2.0 / std::sqrt(2.0));
    CHECK(got.bands <= truth.bands / 2.0 * std::sqrt(2.0));
    CHECK(orientation_difference(got.angle, truth.angle) < 10.0);
    // One octave more, so the finest still reaches the grid's scale.
    CHECK(got.octave_count() == truth.octave_count() + 1);
    // The paper's fBm stays one cycle per cube side.
    CHECK(e.paper.noise.frequency == 1.0);

    const GrayImage luma = photo_luma(photo);
    std::vector<float> sorted = luma.values;
    std::sort(sorted.begin(), sorted.end());
    const TextureSpectrum on_cube = texture_spectrum(luma, photo_pixels_per_side(photo));
    const auto slice_distance = [&](const NoiseParams& noise) {
        return structure_distance(texture_spectrum(matched_noise_slice(noise, 64, sorted), 128.0), on_cube);
    };
    const double estimated = slice_distance(got), photo_scale = slice_distance(truth);
    CAPTURE(estimated, photo_scale);
    CHECK(estimated < 0.5 * photo_scale);
    // evaluate_structure takes the noise in the cube's frame, as the
    // estimate returns it: the chosen fit again, bit for bit.
    const StructureFit again = evaluate_structure(got, photo);
    CHECK(again.distance == e.chosen.distance);
    CHECK(again.coherence == e.chosen.coherence);
}

TEST_CASE("structure estimate: marble bands are told from grain", "[structure]") {
    const NoiseParams truth = marble_truth();
    NoiseParams base;
    base.resolution = 128;
    const StructureEstimate e = estimate_structure(photo_of(truth), base);
    const NoiseParams& got = e.chosen.noise;
    CAPTURE(got.frequency, got.k, got.stretch, got.angle, got.bands, got.warp, e.chosen.distance, e.paper.distance);
    REQUIRE(got.bands >= 6.0);
    REQUIRE(got.bands <= 24.0);
    REQUIRE(std::abs(got.angle - truth.angle) < 10.0);
    REQUIRE(e.chosen.distance < 0.5 * e.paper.distance);
}

TEST_CASE("structure estimate: folded layers of many thicknesses are told from the sine's bands and from grain",
          "[structure]") {
    const NoiseParams truth = layered_truth(9, 8.0, 0.5, 1.41, 60.0);
    NoiseParams base;
    base.resolution = 128;
    const StructureEstimate e = estimate_structure(photo_of(truth), base);
    const NoiseParams& got = e.chosen.noise;
    CAPTURE(got.frequency, got.k, got.stretch, got.angle, got.bands, got.warp, got.layers, e.chosen.distance,
            e.paper.distance);
    REQUIRE(got.layers);
    REQUIRE(orientation_difference(got.angle, truth.angle) < 10.0);
    REQUIRE(e.chosen.distance < 0.5 * e.paper.distance);
}

TEST_CASE("structure estimate: asked for veins, it recovers their frequency and width and keeps the paper's "
          "fBm to compare", "[structure]") {
    NoiseParams truth;
    truth.resolution = 128;
    truth.seed = 9;
    truth.frequency = 4.0;
    truth.k = 0.5;
    truth.veins = true;
    truth.vein_frequency = 1.41;
    truth.vein_width = 0.01;
    NoiseParams base;
    base.resolution = 128;
    base.veins = true;
    const StructureEstimate e = estimate_structure(photo_of(truth), base);
    const NoiseParams& got = e.chosen.noise;
    CAPTURE(got.frequency, got.k, got.stretch, got.bands, got.vein_frequency, got.vein_width, e.chosen.distance,
            e.paper.distance);
    REQUIRE(got.veins);
    REQUIRE_FALSE(e.paper.noise.veins);
    REQUIRE(got.bands == 0.0);
    REQUIRE(got.frequency >= truth.frequency / 2.0);
    REQUIRE(got.frequency <= truth.frequency * 2.0);
    REQUIRE(got.vein_frequency >= truth.vein_frequency / 2.0);
    REQUIRE(got.vein_frequency <= truth.vein_frequency * 2.0);
    REQUIRE(got.vein_width >= truth.vein_width / 2.0);
    REQUIRE(got.vein_width <= truth.vein_width * 2.0);
    REQUIRE(e.chosen.distance < 0.5 * e.paper.distance);
}

TEST_CASE("structure estimate: folds that never turn back are told from folds overturned into rings",
          "[structure]") {
    // One strongly warped layered structure (a·f_0 = 2.8), read by the warp
    // at a tenth of the distance across the layers (long folded layers) or
    // isotropically (rings where folds overturn). Their spectra are alike;
    // their orientation defects are not, and the estimate's slices have the
    // photo's. (Fold and frequency trade against each other, so the fold
    // itself is not what is recovered: the defects are.)
    NoiseParams truth = layered_truth(5, 12.0, 1.4, 2.0, 20.0);
    NoiseParams base;
    base.resolution = 128;
    double photo_defects[2] = {0.0, 0.0};
    for (const int overturned : {0, 1}) {
        truth.fold = overturned ? 1.0 : 0.1;
        const StructureEstimate e = estimate_structure(photo_of(truth), base);
        const NoiseParams& got = e.chosen.noise;
        CAPTURE(truth.fold, got.frequency, got.k, got.bands, got.warp, got.fold, got.layers, e.chosen.distance,
                e.chosen.defects, e.photo.defects);
        photo_defects[overturned] = e.photo.defects;
        REQUIRE(got.bands > 0.0);
        CHECK(e.chosen.defects <= 1.5 * e.photo.defects);
        CHECK(e.chosen.defects >= e.photo.defects / 1.5);
        CHECK(e.chosen.distance < 0.5 * e.paper.distance);
    }
    CAPTURE(photo_defects[0], photo_defects[1]);
    REQUIRE(photo_defects[1] > 2.0 * photo_defects[0]);
}

TEST_CASE("structure estimate: the fold and the warp are found together", "[structure]") {
    // One layer per side folded by a warp of 1.4 sides read at a 20th of the
    // distance across it: long folds, never overturned. Moving the fold and
    // then the warp one at a time, the search stopped at ε = 1 and a warp of
    // 1 (the start's; slice distance 0.18); over both at once it lands on the
    // truth's grid neighbourhood (ε 0.1, warp 1.4: 0.12).
    NoiseParams truth = layered_truth(5, 1.0, 1.4, 1.41, 20.0);
    truth.fold = 0.05;
    NoiseParams base;
    base.resolution = 128;
    const StructureEstimate e = estimate_structure(photo_of(truth), base);
    const NoiseParams& got = e.chosen.noise;
    CAPTURE(got.frequency, got.k, got.bands, got.warp, got.fold, got.layers, e.chosen.distance, e.chosen.defects,
            e.photo.defects);
    REQUIRE(got.layers);
    CHECK(got.fold <= 0.1);
    CHECK(got.warp >= 1.0);
    CHECK(got.warp <= 2.0);
    CHECK(e.chosen.distance < 0.5 * e.paper.distance);
}

TEST_CASE("structure estimate: a one-colour photo keeps the paper's fBm without a search", "[structure]") {
    // No band has power, so no candidate's distance to the photo is defined:
    // the paper's fBm is kept after its own evaluation alone (and a photo
    // with structure is searched: the cases above).
    NoiseParams base;
    base.resolution = 64;
    Photo p;
    p.width = p.height = 64;
    p.levels.assign(64 * 64, Rgb8{120, 160, 110});
    p.foreground.assign(p.levels.size(), 1);
    const StructureEstimate e = estimate_structure(p, base);
    CHECK(e.evaluations == 1);
    CHECK(e.chosen.noise.frequency == 1.0);
    CHECK(e.chosen.noise.bands == 0.0);
    CHECK_FALSE(e.chosen.noise.layers);
    CHECK(e.chosen.distance == e.paper.distance);
}
