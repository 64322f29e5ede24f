// A render split into pieces — sample ranges, pixel tiles, any grouping —
// and merged is bit-identical to one render of all its samples: the random
// numbers are keyed by (seed, pixel, sample) and the film's sums are exact.

#include "jade/geometry/mesh_accel.h"
#include "jade/core/random.h"
#include "jade/geometry/mesh.h"
#include "jade/render/media/homogeneous.h"
#include "jade/render/renderer.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace jade;

namespace {

bool identical(const Film& a, const Film& b) {
    const std::vector<float> x = a.rgba(true), y = b.rgba(true);
    if (x.size() != y.size() || std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) != 0)
        return false;
    for (int py = 0; py < a.height(); ++py)
        for (int px = 0; px < a.width(); ++px) {
            if (a.samples(px, py) != b.samples(px, py)) return false;
            const Spectrum va = a.variance_of_mean(px, py), vb = b.variance_of_mean(px, py);
            if (std::memcmp(&va, &vb, sizeof va) != 0) return false;
        }
    return true;
}

// A medium behind a dielectric under a tinted sky, in `accel`'s mesh.
Scene dielectric_scene(const MeshAccel& accel, const HomogeneousMedium& medium) {
    Scene scene;
    scene.boundary = &accel;
    scene.medium = &medium;
    scene.interface.mode = BoundaryMode::Fresnel;
    scene.environment = Environment(Spectrum(0.2f, 0.3f, 0.4f));
    scene.fit_ray_epsilon();
    return scene;
}

// A camera at (0, 0, 4) looking at the origin.
PinholeCamera camera_on_z(int width, int height) {
    CameraParams cp;
    cp.origin = {0.f, 0.f, 4.f};
    cp.width = width;
    cp.height = height;
    return PinholeCamera(cp);
}

}  // namespace

TEST_CASE("pieces of a render merged are bit-identical to the whole render", "[render_pass]") {
    const TriangleMesh mesh = icosphere(3, 1.f);
    const MeshAccel accel(mesh);
    // A bright, deep medium behind a dielectric, lit by the disc light
    // (through the refracted-cone estimator) and the environment: long
    // paths, wide-ranging sample values.
    const HomogeneousMedium medium(Spectrum(3.8f, 7.2f, 9.6f), Spectrum(0.2f, 0.8f, 2.4f));
    Scene scene = dielectric_scene(accel, medium);
    scene.light = DirectionalLight(glm::vec3(0.3f, 0.8f, 0.5f), 3.f, 20.f);
    const PinholeCamera camera = camera_on_z(24, 20);
    RenderSettings settings;
    settings.seed = 7;
    // The whole render's sample count: the light guide's rays follow it
    // (render/light_guide.h), so every piece is rendered as part of it.
    settings.spp = 37;
    const PixelBounds all{0, 0, 24, 20};
    const Film whole = render_pass(scene, camera, settings, {0, 37}, all);
    REQUIRE(whole.spp() == 37);

    SECTION("uneven sample ranges, merged in either order") {
        for (const std::vector<int>& cuts :
             {std::vector<int>{0, 18, 37}, {0, 5, 6, 30, 37}, {0, 1, 2, 3, 10, 11, 20, 36, 37}}) {
            Film forward(24, 20), backward(24, 20);
            std::vector<Film> pieces;
            for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
                pieces.push_back(render_pass(scene, camera, settings, {cuts[k], cuts[k + 1]}, all));
            for (const Film& f : pieces) forward.merge(f);
            for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) backward.merge(*it);
            CHECK(identical(forward, whole));
            CHECK(identical(backward, whole));
        }
    }
    SECTION("tiles of pixels, each in two sample ranges") {
        Film merged(24, 20);
        for (const PixelBounds& b : {PixelBounds{0, 0, 10, 20}, PixelBounds{10, 0, 24, 7},
                                     PixelBounds{10, 7, 24, 20}})
            for (const SampleRange& r : {SampleRange{0, 21}, SampleRange{21, 37}})
                merged.merge(render_pass(scene, camera, settings, r, b));
        CHECK(identical(merged, whole));
    }
    SECTION("the progressive renderer's passes give the same film") {
        CHECK(identical(render(scene, camera, settings).film, whole));
    }
    SECTION("a progressive render paused and carried on gives the same film and the same passes") {
        const RenderResult once = render(scene, camera, settings);
        ProgressiveRender paused(scene, camera, settings);
        paused.run_to(9);
        CHECK(paused.samples() == 9);
        CHECK_FALSE(paused.finished());
        CHECK(paused.result().film.fewest_samples() == 9);
        CHECK(paused.result().passes.back().spp == 9);
        paused.run_to(9);  // nothing left to do up to 9
        CHECK(paused.result().film.fewest_samples() == 9);
        paused.run_to(100);  // no further than the settings' 37
        CHECK(paused.finished());
        const RenderResult carried = std::move(paused).take();
        CHECK(identical(carried.film, whole));
        CHECK(identical(carried.film, once.film));
        // 9 samples end a pass the doubling would not (1, 1, 2, 4, 8): the
        // passes after it carry on doubling from 9.
        std::vector<int> counts;
        for (const PassRecord& p : carried.passes) counts.push_back(p.spp);
        CHECK(counts == std::vector<int>{1, 2, 4, 8, 9, 18, 36, 37});
        for (std::size_t i = 0; i < carried.passes.size(); ++i) {
            CHECK(carried.passes[i].pass == int(i));
            if (i > 0) CHECK(carried.passes[i].seconds >= carried.passes[i - 1].seconds);
        }
        CHECK(carried.seconds >= carried.passes.back().seconds);
        // The integrator's set-up is counted once, in the render's seconds.
        CHECK(carried.setup_seconds > 0.0);
        CHECK(carried.passes.front().seconds >= carried.setup_seconds);
        CHECK(carried.stopped_by == "spp");
    }
    SECTION("a part's samples less the backdrop are the same samples before a transparent backdrop") {
        // The sky is the backdrop here: edge pixels hold it, the object alone does not.
        ProgressiveRender paused(scene, camera, settings);
        Film object_alone(24, 20);
        paused.run_to(9, nullptr, nullptr, &object_alone);
        RenderSettings transparent = settings;
        transparent.backdrop.transparent = true;
        CHECK(identical(object_alone, render_pass(scene, camera, transparent, {0, 9}, all)));
        CHECK_FALSE(identical(object_alone, render_pass(scene, camera, settings, {0, 9}, all)));
        paused.run_to(37);
        CHECK(identical(std::move(paused).take().film, whole));
    }
    SECTION("a render in halves: merged, the same film; apart, replicates 0-1 and 2-3") {
        // 37 samples: turns of the heroes 0 … 11 and sample 36 (turn 12),
        // turn t in replicate t mod 4 (render/pixel_sampler.h): replicate 0
        // holds 10 samples and the others 9.
        const SplitFilms halves = render_halves(scene, camera, settings);
        CHECK(halves.first.spp() == 19);
        CHECK(halves.second.spp() == 18);
        CHECK(halves.first.fewest_samples() == 19);
        CHECK(identical(halves.merged(), whole));
        // Replicates 1 … 3's counts per pixel (replicate 0 holds the rest).
        for (std::size_t i = 0; i < 24 * 20; ++i) {
            CHECK(halves.first.replicate_counts()[3 * i] == 9);
            CHECK(halves.first.replicate_counts()[3 * i + 1] == 0);
            CHECK(halves.first.replicate_counts()[3 * i + 2] == 0);
            CHECK(halves.second.replicate_counts()[3 * i] == 0);
            CHECK(halves.second.replicate_counts()[3 * i + 1] == 9);
            CHECK(halves.second.replicate_counts()[3 * i + 2] == 9);
        }
    }
    SECTION("a render in quarters: the same halves, and each quarter one replicate") {
        const SplitFilms halves = render_halves(scene, camera, settings);
        const SplitFilms quarters = render_quarters(scene, camera, settings);
        CHECK(halves.quarters.empty());
        CHECK(identical(quarters.first, halves.first));
        CHECK(identical(quarters.second, halves.second));
        REQUIRE(quarters.quarters.size() == 4);
        for (int i = 0; i < 4; ++i) {
            const ImageF32& q = quarters.quarters[std::size_t(i)];
            CHECK(q.width == 24);
            CHECK(q.channels == 4);
            for (int j = 0; j < i; ++j) CHECK(q.pixels != quarters.quarters[std::size_t(j)].pixels);
        }
        // A quarter's coverage is its replicate's share of object hits: the
        // four together hold the whole render's hits.
        for (int y = 0; y < 20; ++y)
            for (int x = 0; x < 24; ++x) {
                const std::size_t i = std::size_t(y) * 24 + x;
                const int counts[4] = {10, 9, 9, 9};
                double hits = 0.0;
                for (int r = 0; r < 4; ++r) hits += double(quarters.quarters[std::size_t(r)].pixels[4 * i + 3]) * counts[r];
                CHECK(hits == Approx(double(whole.object_hits()[i])).margin(1e-4));
            }
    }
    SECTION("a different seed gives a different image") {
        settings.seed = 8;
        CHECK_FALSE(identical(render_pass(scene, camera, settings, {0, 37}, all), whole));
    }
}

TEST_CASE("a time budget that runs out in the first pass stops it, and the pixels it left are counted",
          "[render_pass]") {
    const TriangleMesh mesh = icosphere(2, 1.f);
    const MeshAccel accel(mesh);
    const HomogeneousMedium medium(Spectrum(2.f), Spectrum(0.5f));
    Scene scene;
    scene.boundary = &accel;
    scene.medium = &medium;
    scene.fit_ray_epsilon();
    CameraParams cp;
    cp.origin = {0.f, 0.f, 4.f};
    cp.width = 16;
    cp.height = 12;
    const PinholeCamera camera(cp);
    RenderSettings settings;
    settings.spp = 64;
    // A budget already spent when the first pixel starts: no pixel gets a
    // sample, and the render says so instead of running the pass out.
    settings.time_limit = 1e-9;
    const RenderResult cut = render(scene, camera, settings);
    CHECK(cut.stopped_by == "time");
    CHECK(cut.unsampled_pixels == 16u * 12u);
    CHECK(cut.film.spp() == 0);
    REQUIRE(cut.passes.size() == 1);
    CHECK(cut.passes[0].spp == 0);
    CHECK(cut.passes[0].mean_spp == 0.0);
    // Without a budget every pixel holds every sample; the first pass is one sample.
    settings.time_limit = 0.0;
    const RenderResult whole = render(scene, camera, settings);
    CHECK(whole.unsampled_pixels == 0u);
    CHECK(whole.film.fewest_samples() == 64);
    CHECK(whole.passes[0].spp == 1);
    for (const PassRecord& p : whole.passes) CHECK(p.mean_spp == double(p.spp));
    CHECK(format_spp(whole.passes.back()) == "64 spp");
}

TEST_CASE("a pass cut short by its time budget reports its fewest samples and its mean", "[render]") {
    // The film of a cut pass: some pixels hold a sample more than others.
    Film film(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x)
            for (int k = 0; k < (x < 3 ? 3 : 2); ++k) film.add_sample(x, y, Spectrum(1.f), true, k % 3, k);
    CHECK(film.fewest_samples() == 2);
    CHECK(film.spp() == 3);
    CHECK(film.mean_samples() == Approx(22.0 / 8.0));
    PassRecord cut;
    cut.spp = film.fewest_samples();
    cut.mean_spp = film.mean_samples();
    CHECK(format_spp(cut) == "at least 2 spp (2.8 on average)");
}

namespace {
// A small sphere off the view's axis, so that most pixels see past it.
TriangleMesh off_axis_sphere() {
    TriangleMesh mesh = icosphere(3, 0.5f);
    for (glm::vec3& p : mesh.positions) p += glm::vec3(1.f, 0.6f, 0.f);
    return mesh;
}
}  // namespace

TEST_CASE("no camera ray through a pixel outside pixels_seeing meets the mesh", "[render_pass]") {
    const TriangleMesh mesh = off_axis_sphere();
    const MeshAccel accel(mesh);
    CameraParams cp;
    cp.origin = {0.f, 0.f, 4.f};
    cp.width = 64;
    cp.height = 48;
    const PinholeCamera camera(cp);
    const PixelBounds seen = pixels_seeing(camera, mesh.positions);
    // The sphere covers about a tenth of the film: the rectangle about it is
    // much smaller than the film, and holds every pixel whose centre meets it.
    CHECK((seen.x1 - seen.x0) * (seen.y1 - seen.y0) < 64 * 48 / 4);
    SplitMix64 rng(3);
    int hits = 0, outside = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            const bool inside = x >= seen.x0 && x < seen.x1 && y >= seen.y0 && y < seen.y1;
            // The pixel's corners and centre, then random points of its square.
            for (int k = 0; k < 21; ++k) {
                const float u = k < 4 ? float(k % 2) : k == 4 ? 0.5f : float(rng.uniform());
                const float v = k < 4 ? float(k / 2) : k == 4 ? 0.5f : float(rng.uniform());
                const glm::vec3 d = camera.direction((float(x) + u) / 64.f, (float(y) + v) / 48.f);
                const bool hit = accel.intersect(camera.origin(), d, 0.f, 1e30f).has_value();
                hits += hit ? 1 : 0;
                if (!inside) {
                    ++outside;
                    if (hit) FAIL_CHECK("pixel (" << x << ", " << y << ") sees the mesh outside the rectangle");
                }
            }
        }
    CHECK(hits > 1000);
    CHECK(outside > 21 * 64 * 48 / 2);

    SECTION("a camera inside the mesh's reach, or a vertex behind it, keeps the whole film") {
        cp.origin = {1.f, 0.6f, 0.f};
        cp.target = {1.f, 0.6f, -1.f};
        const PixelBounds within = pixels_seeing(PinholeCamera(cp), mesh.positions);
        CHECK((within.x0 == 0 && within.y0 == 0 && within.x1 == 64 && within.y1 == 48));
        cp.origin = {1.f, 0.6f, 0.3f};  // half the sphere behind the camera's plane
        const PixelBounds straddling = pixels_seeing(PinholeCamera(cp), mesh.positions);
        CHECK((straddling.x0 == 0 && straddling.y0 == 0 && straddling.x1 == 64 && straddling.y1 == 48));
    }
}

TEST_CASE("pixels that cannot see the object hold the backdrop alone, with every sample", "[render_pass]") {
    const TriangleMesh mesh = off_axis_sphere();
    const MeshAccel accel(mesh);
    const HomogeneousMedium medium(Spectrum(3.8f, 7.2f, 9.6f), Spectrum(0.2f, 0.8f, 2.4f));
    const Scene scene = dielectric_scene(accel, medium);
    const PinholeCamera camera = camera_on_z(32, 24);
    RenderSettings settings;
    settings.seed = 5;
    settings.spp = 13;
    const Film film = render_pass(scene, camera, settings, {0, 13}, {0, 0, 32, 24});
    const PixelBounds seen = pixels_seeing(camera, mesh.positions);
    int skipped = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) {
            if (x >= seen.x0 && x < seen.x1 && y >= seen.y0 && y < seen.y1) continue;
            ++skipped;
            CHECK(film.samples(x, y) == 13);
            CHECK(film.coverage(x, y) == 0.f);
            const Spectrum m = film.mean(x, y), v = film.variance_of_mean(x, y);
            for (int c = 0; c < 3; ++c) {
                CHECK(m[c] == scene.environment.radiance_toward(glm::vec3(0.f, 0.f, -1.f))[c]);
                CHECK(v[c] == 0.f);
            }
        }
    CHECK(skipped > 32 * 24 / 2);
    // Split into pieces, the skipped pixels merge like the traced ones.
    Film merged = render_pass(scene, camera, settings, {0, 6}, {0, 0, 32, 24});
    merged.merge(render_pass(scene, camera, settings, {6, 13}, {0, 0, 32, 24}));
    CHECK(identical(merged, film));
}
