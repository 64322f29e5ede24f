#pragma once
// Helpers for the rendering tests: a box mesh, a scene around a medium, and
// statistical comparison of a film with an expected image using both
// images' per-pixel variance.

#include "jade/render/film.h"
#include "jade/render/scene.h"
#include "jade/io/image_io.h"
#include "jade/geometry/mesh.h"

#include <cmath>
#include <functional>
#include <ostream>
#include <utility>
#include <vector>

namespace jade_test {

// The object `accel` filled with `medium` behind a boundary of `mode`,
// under a constant environment `env`; the light is the caller's.
inline jade::Scene basic_scene(const jade::Boundary& accel, const jade::Medium* medium, jade::BoundaryMode mode,
                               jade::Spectrum env) {
    jade::Scene s;
    s.boundary = &accel;
    s.medium = medium;
    s.interface.mode = mode;
    s.environment = jade::Environment(env);
    s.fit_ray_epsilon();
    return s;
}

// A 64 × 32 lat-long HDR sky: a dim gradient, a black band over the last
// rows, a sun of sun_size² texels at `sun` times the sky's brightness
// (rows 8…, columns 40…: 40–56° from +y, a quarter turn from −z toward +x),
// and the small negative texels real HDRs hold around a bright sun.
inline jade::ImageF32 sun_and_sky_image(int sun_size, float sun) {
    jade::ImageF32 img;
    img.width = 64;
    img.height = 32;
    img.channels = 3;
    img.pixels.assign(std::size_t(64 * 32 * 3), 0.f);
    auto at = [&](int x, int y, int c) -> float& { return img.pixels[std::size_t((y * 64 + x) * 3 + c)]; };
    for (int y = 0; y < 28; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) at(x, y, c) = 0.1f + 0.01f * float(y + c);
    for (int y = 8; y < 8 + sun_size; ++y)
        for (int x = 40; x < 40 + sun_size; ++x)
            for (int c = 0; c < 3; ++c) at(x, y, c) = 0.1f * sun * float(c + 1);
    at(40, 7, 0) = -0.004f;
    at(40 + sun_size + 1, 8 + sun_size, 2) = -0.002f;
    return img;
}

// Axis-aligned box [lo, hi], outward winding, face normals.
inline jade::TriangleMesh box_mesh(glm::vec3 lo, glm::vec3 hi) {
    jade::TriangleMesh m;
    m.path = "(test box)";
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    // Corner index bits: x = 1, y = 2, z = 4.
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    m.normals.assign(m.positions.size(), glm::vec3(0, 0, 1));  // unused: flat shading
    return m;
}

// Two closed meshes as one (two bodies of one medium).
inline jade::TriangleMesh merged_mesh(const jade::TriangleMesh& a, const jade::TriangleMesh& b) {
    jade::TriangleMesh m = a;
    const auto base = std::uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
    m.normals.insert(m.normals.end(), b.normals.begin(), b.normals.end());
    for (auto t : b.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    return m;
}

// An image to compare against: value and variance of that value per pixel.
struct Expected {
    int width = 0, height = 0;
    std::function<double(int x, int y, int c)> value;
    std::function<double(int x, int y, int c)> variance;
    // Pixels left out of the comparison (none when empty).
    std::function<bool(int x, int y)> skip;
};

// The reference image (and its variance image) averaged over f x f pixel
// blocks, so it matches a film rendered at 1/f the resolution with a box filter.
inline Expected downsampled(const jade::ImageF32& ref, const jade::ImageF32& var, int f) {
    Expected e;
    e.width = ref.width / f;
    e.height = ref.height / f;
    auto avg = [f](const jade::ImageF32& img, int x, int y, int c, double scale) {
        double s = 0;
        for (int j = 0; j < f; ++j)
            for (int i = 0; i < f; ++i) s += img.at(x * f + i, y * f + j, c);
        return s * scale;
    };
    const double n = double(f) * f;
    e.value = [&ref, avg, n](int x, int y, int c) { return avg(ref, x, y, c, 1.0 / n); };
    e.variance = [&var, avg, n](int x, int y, int c) { return avg(var, x, y, c, 1.0 / (n * n)); };
    return e;
}

// z-scores of the film against the expectation over square blocks of
// `block` pixels per channel: (Σ film − Σ expected) / sqrt(Σ Var film + Σ Var expected).
// Pixels are independent, so the variances of a block's sums add.
struct BlockZ {
    double max_abs_z = 0.0;
    double whole_image_z[3] = {0, 0, 0};
    double mean_difference[3] = {0, 0, 0};
    int blocks = 0;
    int worst_x = -1, worst_y = -1, worst_channel = -1;  // the block with the largest |z|
    double worst_difference = 0, worst_variance = 0;      // its summed difference and variance
};

inline std::ostream& operator<<(std::ostream& os, const BlockZ& z) {
    return os << "max block |z| " << z.max_abs_z << " at block (" << z.worst_x << ", " << z.worst_y
              << ") channel " << z.worst_channel << " (sum of differences " << z.worst_difference
              << ", variance " << z.worst_variance << "); whole-image z " << z.whole_image_z[0] << " "
              << z.whole_image_z[1] << " " << z.whole_image_z[2] << "; mean difference "
              << z.mean_difference[0] << " " << z.mean_difference[1] << " " << z.mean_difference[2];
}

inline BlockZ block_z_scores(const jade::Film& film, const Expected& e, int block) {
    BlockZ r;
    double all_d[3] = {0, 0, 0}, all_v[3] = {0, 0, 0};
    for (int by = 0; by < film.height(); by += block)
        for (int bx = 0; bx < film.width(); bx += block) {
            ++r.blocks;
            for (int c = 0; c < 3; ++c) {
                double d = 0, v = 0;
                for (int y = by; y < std::min(by + block, film.height()); ++y)
                    for (int x = bx; x < std::min(bx + block, film.width()); ++x) {
                        if (e.skip && e.skip(x, y)) continue;
                        d += double(film.mean(x, y)[c]) - e.value(x, y, c);
                        v += double(film.variance_of_mean(x, y)[c]) + e.variance(x, y, c);
                    }
                all_d[c] += d;
                all_v[c] += v;
                const double zb = v > 0 ? std::abs(d) / std::sqrt(v) : (std::abs(d) > 1e-6 ? 1e30 : 0.0);
                if (zb > r.max_abs_z) {
                    r.max_abs_z = zb;
                    r.worst_x = bx;
                    r.worst_y = by;
                    r.worst_channel = c;
                    r.worst_difference = d;
                    r.worst_variance = v;
                }
            }
        }
    for (int c = 0; c < 3; ++c) {
        r.whole_image_z[c] = all_v[c] > 0 ? all_d[c] / std::sqrt(all_v[c]) : (all_d[c] == 0 ? 0 : 1e30);
        r.mean_difference[c] = all_d[c] / (double(film.width()) * film.height());
    }
    return r;
}

// The same film with its replicates' sums taken away (every sample in
// replicate 0): its variance is then read from the samples as if they were
// independent, within the hero strata (render/film.h).
inline jade::Film without_replicates(const jade::Film& f) {
    jade::Film::Sums s = jade::Film::zero_sums(f.width(), f.height());
    s.sum = f.sums();
    s.sum_sq = f.sums_of_squares();
    s.count = f.counts();
    s.hits = f.object_hits();
    s.stratum_sum = f.stratum_sums();
    s.stratum_count = f.stratum_counts();
    return jade::Film::from_sums(std::move(s));
}

}  // namespace jade_test
