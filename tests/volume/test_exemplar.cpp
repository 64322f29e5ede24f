// The photo swept through the cube (volume/exemplar.h): the exemplar is the
// photo at the cube's scale, repeats without a seam, and every slice of the
// volume is the photo itself, moved by a smooth offset.

#include "jade/volume/exemplar.h"
#include "jade/volume/material_volume.h"
#include "jade/volume/structure_estimate.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <functional>

using namespace jade;

namespace {

// A w×h grey photo with level f(x, y), every pixel foreground.
Photo grey_photo(int w, int h, const std::function<int(int, int)>& f) {
    Photo p;
    p.width = w, p.height = h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const auto l = std::uint8_t(f(x, y));
            p.levels.push_back({l, l, l});
        }
    p.foreground.assign(p.levels.size(), 1);
    return p;
}

}  // namespace

TEST_CASE("the exemplar is the photo's luma at the cube's scale", "[exemplar]") {
    // 2×2 blocks of one level each: at 32 voxels per side a voxel covers one
    // block exactly, so the exemplar is the blocks' levels.
    auto block_level = [](int x, int y) { return 10 + 7 * ((x / 2) % 5) + 31 * ((y / 2) % 3); };
    const Photo photo = grey_photo(64, 64, block_level);
    const Exemplar e = make_exemplar(photo, 32);
    REQUIRE(e.side == 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            CHECK(e.values[std::size_t(y) * 32 + x] == Approx(block_level(2 * x, 2 * y)).margin(1e-3));
    // Spanning two cube sides, the photo's 64 pixels cover 2 sides, 32
    // pixels a side: at 32 voxels per side a voxel is one pixel.
    Photo slab = photo;
    slab.span = 2.0;
    const Exemplar wide = make_exemplar(slab, 32);
    REQUIRE(wide.side == 64);
    CHECK(wide.values[std::size_t(5) * 64 + 9] == Approx(block_level(9, 5)).margin(1e-3));
    // A close-up spanning half a side: 128 pixels a side, four a voxel,
    // each voxel the mean of its 4×4.
    slab.span = 0.5;
    const Exemplar close = make_exemplar(slab, 32);
    REQUIRE(close.side == 16);
    CHECK(close.values[3] == Approx(10 + 7 * 1.5 + 31 * 0.5).margin(1e-3));
    // A slab spanning four sides: 16 pixels a side, half a pixel a voxel,
    // read between pixels: voxel 3's centre is pixel 0.5·3.5 − 0.5 = 1.25.
    slab.span = 4.0;
    const Exemplar wider = make_exemplar(slab, 32);
    REQUIRE(wider.side == 128);
    CHECK(wider.values[3] == Approx(0.75 * block_level(1, 0) + 0.25 * block_level(2, 0)).margin(1e-3));
}

TEST_CASE("the exemplar repeats periodically where it tiles and mirrored where not", "[exemplar]") {
    const double pi = std::acos(-1.0);
    // Three whole periods across: it tiles.
    const Photo tiling = grey_photo(48, 48, [&](int x, int y) {
        return int(std::lround(128 + 60 * std::sin(2 * pi * 3 * (x + 0.5) / 48) * std::cos(2 * pi * 2 * (y + 0.5) / 48)));
    });
    const Exemplar t = make_exemplar(tiling, 48);
    CHECK(t.periodic);
    CHECK(t.at(-1, 5) == t.values[std::size_t(5) * 48 + 47]);
    CHECK(t.at(50, 49) == t.values[std::size_t(1) * 48 + 2]);
    // A ramp jumps from its top to its bottom at the wrap: mirrored.
    const Photo ramp = grey_photo(48, 48, [](int x, int) { return 20 + 4 * x; });
    const Exemplar r = make_exemplar(ramp, 48);
    CHECK_FALSE(r.periodic);
    CHECK(r.at(-1, 0) == r.values[0]);
    CHECK(r.at(-3, 0) == r.values[2]);
    CHECK(r.at(48, 0) == r.values[47]);
    CHECK(r.at(50, 0) == r.values[45]);
}

TEST_CASE("every slice of the sweep is the photo, moved by a smooth offset", "[exemplar]") {
    const Photo photo = grey_photo(64, 64, [](int x, int y) { return (x * 7 + y * 13) % 200 + 20; });
    const Exemplar e = make_exemplar(photo, 64);
    const int s = 64;
    std::vector<float> slice(std::size_t(s) * s);
    // No wander: the photo drawn straight through, seen from +z as the photo is.
    swept_slice(e, s, 9, 1, 0.0, slice.data());
    for (int y = 0; y < s; ++y)
        for (int x = 0; x < s; ++x) CHECK(slice[std::size_t(y) * s + x] == e.values[std::size_t(s - 1 - y) * s + x]);
    // With wander: each slice the exemplar moved by its offset, the offsets
    // within the wander and changing by a voxel or two from slice to slice.
    const double wander = 0.25;
    std::array<int, 2> previous = sweep_offset(0, s, 1, wander);
    int moved = 0;
    for (int z = 0; z < s; ++z) {
        const std::array<int, 2> d = sweep_offset(z, s, 1, wander);
        CHECK(std::abs(d[0]) <= wander * s);
        CHECK(std::abs(d[1]) <= wander * s);
        CHECK(std::abs(d[0] - previous[0]) <= 2);
        CHECK(std::abs(d[1] - previous[1]) <= 2);
        moved += d != previous;
        previous = d;
        swept_slice(e, s, z, 1, wander, slice.data());
        for (int y = 0; y < s; y += 5)
            for (int x = 0; x < s; x += 3) CHECK(slice[std::size_t(y) * s + x] == e.at(x + d[0], s - 1 - y + d[1]));
    }
    CHECK(moved > 8);  // it does wander
}

TEST_CASE("a volume swept from the photo has the photo's structure in its slices", "[exemplar]") {
    // Folded layers, the photo of `layered` at 96 pixels: its slices'
    // structure distance to the photo is what the photo's own resampling
    // leaves, far below what the paper's fBm matched to the same colours
    // scores (texture_spectrum.h measures both against the photo).
    NoiseParams layered;
    layered.resolution = 96, layered.seed = 5, layered.layers = true, layered.bands = 6.0, layered.warp = 0.5;
    layered.frequency = 2.0, layered.k = 0.8, layered.angle = 30.0;
    std::vector<float> ramp;
    for (int i = 0; i < 96 * 96; ++i) ramp.push_back(30.f + 190.f * float(i) / float(96 * 96));
    const GrayImage g = matched_noise_slice(layered, 48, ramp);
    const Photo photo = grey_photo(96, 96, [&](int x, int y) { return int(std::lround(g.values[std::size_t(y) * 96 + x])); });

    NoiseParams swept;
    swept.resolution = 96, swept.exemplar = true;
    const MaterialVolume volume = build_material_volume(photo, swept, MatchMode::Joint, OpticalParams{});
    NoiseParams paper;
    paper.resolution = 96;
    const MaterialVolume fbm = build_material_volume(photo, paper, MatchMode::Joint, OpticalParams{});
    const StructureFit from_photo = measure_slice_structure(volume.levels, 96, photo);
    const StructureFit from_fbm = measure_slice_structure(fbm.levels, 96, photo);
    CHECK(from_photo.distance < 0.05);
    CHECK(from_fbm.distance > 0.5);
    // The photo's own orientation and coherence, within the measure's
    // resolution (the two slices are the photo moved, whole).
    const TextureSpectrum target = texture_spectrum(photo_luma(photo), 96.0);
    CHECK(from_photo.coherence == Approx(target.coherence).margin(0.05));
    CHECK(from_photo.strength == Approx(target.strength).margin(0.05));
    // Across them (normal to x and to y) the sweep's slices are the photo's
    // rows and columns drawn out in depth: stripes, further from the photo
    // than the slices facing the camera by far, and more strongly oriented
    // than even these folded layers. The fBm, isotropic, looks alike
    // whichever way it is cut.
    const StructureFit across_photo = measure_slice_structure_across(volume.levels, 96, photo);
    const StructureFit across_fbm = measure_slice_structure_across(fbm.levels, 96, photo);
    UNSCOPED_INFO("photo strength " << target.strength << " coherence " << target.coherence << "; across the sweep "
                  << across_photo.distance << ", " << across_photo.strength << ", " << across_photo.coherence
                  << "; fBm facing " << from_fbm.distance << ", " << from_fbm.strength << " across "
                  << across_fbm.distance << ", " << across_fbm.strength);
    CHECK(across_photo.distance > 0.15);
    CHECK(across_photo.distance > 4.0 * from_photo.distance);
    CHECK(across_photo.strength > target.strength + 0.1);
    CHECK(across_fbm.strength == Approx(from_fbm.strength).margin(0.15));
    CHECK(across_fbm.distance == Approx(from_fbm.distance).epsilon(0.3));
    // Every slice holds the photo's histogram (colour matching, §4.2).
    const std::size_t m = 96 * 96;
    std::array<int, 256> in_photo{}, in_slice{};
    for (const Rgb8& c : photo.levels) ++in_photo[c[0]];
    for (std::size_t i = 0; i < m; ++i) ++in_slice[volume.levels[std::size_t(70) * m + i][0]];
    CHECK(in_photo == in_slice);
}
