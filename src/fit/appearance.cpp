#include "jade/fit/appearance.h"

#include "jade/core/display.h"
#include "jade/core/error.h"
#include "jade/core/math.h"
#include "jade/volume/structure_estimate.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace jade {

double render_pixels_per_side(const CameraParams& camera, const Cube& cube) {
    const glm::dvec3 centre(cube.min[0] + 0.5 * cube.side, cube.min[1] + 0.5 * cube.side,
                            cube.min[2] + 0.5 * cube.side);
    const double distance = glm::length(glm::dvec3(camera.origin) - centre);
    const double footprint = 2.0 * distance * std::tan(radians(0.5 * double(camera.fov_degrees))) / camera.width;
    return cube.side / footprint;
}

TextureSpectrum photo_spectrum(const Photo& photo) {
    return texture_spectrum(photo_luma(photo), photo_pixels_per_side(photo));
}

RgbHistogram photo_block_histogram(const Photo& photo, double render_pixels_per_side) {
    const int b = std::max(1, int(std::lround(photo_pixels_per_side(photo) / render_pixels_per_side)));
    std::vector<Rgb8> blocks;
    for (int y0 = 0; y0 + b <= photo.height; y0 += b)
        for (int x0 = 0; x0 + b <= photo.width; x0 += b) {
            double sum[3] = {0, 0, 0};
            int n = 0;
            for (int y = y0; y < y0 + b; ++y)
                for (int x = x0; x < x0 + b; ++x) {
                    const std::size_t i = std::size_t(y) * photo.width + x;
                    if (!photo.foreground[i]) continue;
                    for (int c = 0; c < 3; ++c) sum[c] += srgb_decode(photo.levels[i][c] / 255.0);
                    ++n;
                }
            if (2 * n < b * b) continue;  // a block mostly of background
            blocks.push_back({display_level(sum[0] / n), display_level(sum[1] / n), display_level(sum[2] / n)});
        }
    return RgbHistogram::of(blocks.empty() ? photo.foreground_levels() : blocks);
}

std::array<double, 3> photo_spread(const Photo& photo, double render_pixels_per_side) {
    const RgbHistogram h = photo_block_histogram(photo, render_pixels_per_side);
    return {h.spread(0), h.spread(1), h.spread(2)};
}

QuietBlock quiet_block(const Photo& photo, const SplitFilms& render, const SplitFilms& shading, float exposure,
                       double render_pixels_per_side, int first, double share) {
    QuietBlock q;
    q.block = std::clamp(first, 1, kMaxMaterialBlock);
    for (;;) {
        q.spread = material_spread(render, shading, exposure, q.block);
        q.photo_spread = photo_spread(photo, render_pixels_per_side / q.block);
        // How many times too noisy, in the channel that is most.
        double excess = 0.0;
        for (int c = 0; c < 3; ++c)
            excess = std::max(excess, q.spread.noise[c] / std::max(share * q.photo_spread[c], 1e-9));
        q.quiet = excess <= 1.0;
        if (q.quiet || q.block == kMaxMaterialBlock) return q;
        // Independent pixels' noise falls as 1/block, and the photo's spread
        // falls too as its blocks grow: no block below this one is quiet.
        const int next = int(std::ceil(q.block * std::min(excess, double(kMaxMaterialBlock))));
        q.block = std::clamp(next, q.block + 1, kMaxMaterialBlock);
    }
}

namespace {

// D at every block from 1 to kMaxBlock pixels, and the block D is read at
// (quiet_block at kDNoiseShare from m.block).
void choose_d_block(MaterialAppearance& m, const Photo& photo, const SplitFilms& render, const SplitFilms& shading,
                    float exposure, double render_pixels_per_side) {
    const Film whole = render.merged(), whole_shading = shading.merged();
    for (int b = 1; b <= MaterialAppearance::kMaxBlock; ++b) {
        const RgbHistogram material =
            RgbHistogram::of(flat_render(whole, whole_shading, exposure, b).foreground_levels());
        const RgbHistogram scan = photo_block_histogram(photo, render_pixels_per_side / b);
        for (int c = 0; c < 3; ++c) m.d_by_block[b - 1][c] = histogram_distance(material, scan, c);
    }
    const QuietBlock q = quiet_block(photo, render, shading, exposure, render_pixels_per_side, m.block,
                                     MaterialAppearance::kDNoiseShare);
    m.d_block = q.block;
    m.d_noise = q.spread.noise;
    m.d_photo_spread = q.photo_spread;
    m.d = m.d_by_block[m.d_block - 1];
}

}  // namespace

ShadingReach shading_reach(const Photo& photo, const Film& shading, float exposure, double render_pixels_per_side) {
    ShadingReach r;
    const RgbHistogram stone =
        RgbHistogram::of(shaded_photo(photo, shading, exposure, render_pixels_per_side).foreground_levels());
    const RgbHistogram photo_levels = RgbHistogram::of(photo.foreground_levels());
    for (int c = 0; c < 3; ++c) r.d_stone[c] = stone.total ? histogram_distance(stone, photo_levels, c) : -1.0;
    r.d_least = least_material_distance(photo, shading, exposure);
    return r;
}

MaterialAppearance compare_material(const Photo& photo, const SplitFilms& render, const SplitFilms& shading,
                                    float exposure, double render_pixels_per_side) {
    MaterialAppearance m;
    const Film whole = render.merged();
    m.block = material_block(whole.estimated_relative_error());
    const double blocks_per_side = render_pixels_per_side / m.block;
    const RgbHistogram material =
        RgbHistogram::of(flat_render(whole, shading.merged(), exposure, m.block).foreground_levels());
    const RgbHistogram scan = photo_block_histogram(photo, blocks_per_side);
    m.blocks = material.total;
    // S and the spectrum from what the two halves share (fit/display.h,
    // material_spread): the render's noise is taken out of both.
    const MaterialSpread spread = material_spread(render, shading, exposure, m.block);
    m.spectrum = texture_cross_spectrum(photo_luma(flat_render(render.first, shading.first, exposure, m.block)),
                                        photo_luma(flat_render(render.second, shading.second, exposure, m.block)),
                                        blocks_per_side);
    const TextureSpectrum scan_spectrum = photo_spectrum(photo);
    m.structure = structure_distance(m.spectrum, scan_spectrum);
    m.structure_error = structure_distance_error(m.spectrum, scan_spectrum);
    choose_d_block(m, photo, render, shading, exposure, render_pixels_per_side);
    const ShadingReach reach = shading_reach(photo, shading.merged(), exposure, render_pixels_per_side);
    m.d_stone = reach.d_stone;
    m.d_least = reach.d_least;
    m.structure_stone = structure_distance(
        texture_cross_spectrum(photo_luma(shaded_photo(photo, shading.first, exposure, render_pixels_per_side)),
                               photo_luma(shaded_photo(photo, shading.second, exposure, render_pixels_per_side)),
                               render_pixels_per_side),
        scan_spectrum);
    for (int c = 0; c < 3; ++c) {
        m.s_material[c] = spread.s[c];
        m.s_noise[c] = spread.noise[c];
        m.s_photo[c] = scan.spread(c);
    }
    // Against the photo's blocks that D_material was taken against.
    m.d_least_as_near = least_material_distance_as_near(
        photo, shading.merged(), exposure, m.d, photo_block_histogram(photo, render_pixels_per_side / m.d_block));
    return m;
}

Appearance compare_appearance(const RgbHistogram& photo_histogram, const TextureSpectrum& photo,
                              const DisplayStatistics& render, double pixels_per_side) {
    Appearance a;
    for (int c = 0; c < 3; ++c) {
        a.a_photo[c] = photo_histogram.mean(c);
        a.a_render[c] = render.a[c];
        a.s_photo[c] = photo_histogram.spread(c);
        a.s_render[c] = render.s[c];
        a.d[c] = histogram_distance(render.histogram, photo_histogram, c);
    }
    a.photo = photo;
    // From the halves where the film has them: the subtracted floor bounds
    // the noise from above (the channels' noise taken as fully correlated),
    // and where it exceeds a fine band's power the band falls under the
    // noise (the cow's 90-cycle band under Onyx010 did; held empty, as
    // before bands under the noise read their detection limit, it read 3–4
    // decades below the photo's).
    a.render = render.luma_halves[0].width > 0
                   ? texture_cross_spectrum(render.luma_halves[0], render.luma_halves[1], pixels_per_side)
                   : texture_spectrum(render.luma, pixels_per_side, render.luma_noise_variance);
    a.structure = structure_distance(a.render, a.photo);
    a.structure_error = structure_distance_error(a.render, a.photo);
    return a;
}

SpreadReading read_spread(const MaterialSpread& spread, const std::array<double, 3>& photo_spread, int c,
                          double s_tolerance) {
    const double larger = std::max({photo_spread[c], spread.s[c], s_tolerance});
    SpreadReading r;
    r.noise_limit = kSpreadNoiseShare * larger;
    r.scatter_limit = std::max(kSpreadScatterShare * larger * larger, kSpreadScatterFloor);
    r.quiet = spread.noise[c] <= r.noise_limit;
    r.steady = spread.scatter[c] <= r.scatter_limit;
    return r;
}

int spp_for_noise(int spp, double noise, double limit) {
    if (!(spp > 0)) throw Error("internal: spp_for_noise needs a positive sample count");
    if (!(limit > 0.0)) return 0;
    const double needed = double(spp) * std::pow(noise / limit, 3.0);
    constexpr int kMost = 1 << 20;
    int n = spp;
    while (n < needed && n < kMost) n *= 2;
    return n >= needed ? n : 0;
}

}  // namespace jade
