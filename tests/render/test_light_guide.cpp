// The light guide against geometry (render/light_guide.h): under a flat face
// its histograms point back along Snell's refraction, and along the beam's
// reflection off the floor; beside a wall they point back along the beam
// the wall mirrors into the slab, one cell beyond the beam's edge too; its
// lobe under the flat face points along Snell's refraction and spans the
// disc's image through the face; it is a normalised density; a convex
// object has no mirrored chain; a delta light has no guide; the threads do
// not change it. The truths are Snell's and the mirror's laws, written here.

#include "jade/geometry/mesh_accel.h"
#include "jade/render/light_estimator.h"
#include "jade/render/light_guide.h"
#include "jade/render/media/homogeneous.h"
#include "jade/render/renderer.h"
#include "jade/render/scene.h"

#include "support/render_test_util.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <tbb/task_arena.h>

#include <cmath>
#include <vector>

using namespace jade;

namespace {


Scene guide_scene(const MeshAccel& accel, const Medium& medium, const glm::vec3& toward_light, float radius) {
    Scene s = jade_test::basic_scene(accel, &medium, BoundaryMode::Split, Spectrum(0.f));
    s.light = DirectionalLight(toward_light, 3.f, radius);
    return s;
}

// The mean of n directions drawn from histogram h, normalised.
glm::vec3 mean_direction(const LightGuide& guide, int h, int n = 20000) {
    SplitMix64 rng(3);
    glm::dvec3 sum(0.0);
    for (int k = 0; k < n; ++k)
        sum += glm::dvec3(guide.sample_bins(h, float(rng.uniform()), float(rng.uniform()), float(rng.uniform())));
    return glm::vec3(glm::normalize(sum));
}

double angle_degrees(const glm::vec3& a, const glm::vec3& b) {
    return std::acos(std::clamp(double(glm::dot(glm::normalize(a), glm::normalize(b))), -1.0, 1.0)) * 180.0 / kPiD;
}

}  // namespace

TEST_CASE("under a flat face the guide points back along Snell's refraction and the floor's mirror",
          "[light_guide]") {
    // A slab 0 ≤ z ≤ 1 under a 5° disc 40° from the normal. Refracted in
    // (IOR 1.6), the light travels at θ_i = asin(sin 40° / 1.6) = 23.7°:
    // toward the light is (sin θ_i, 0, cos θ_i); after the floor's mirror it
    // is (sin θ_i, 0, −cos θ_i).
    const TriangleMesh slab = jade_test::box_mesh({-20, -20, 0}, {20, 20, 1});
    const MeshAccel accel(slab, true);
    const HomogeneousMedium medium(Spectrum(0.5f), Spectrum(0.1f));
    const double theta_o = 40.0 * kPiD / 180.0, theta_i = std::asin(std::sin(theta_o) / 1.6);
    const Scene s = guide_scene(accel, medium, {float(std::sin(theta_o)), 0.f, float(std::cos(theta_o))}, 5.f);
    const LightGuide guide(s, 1);
    REQUIRE_FALSE(guide.empty());
    const glm::vec3 p(0.f, 0.f, 0.5f);
    const glm::vec3 direct(float(std::sin(theta_i)), 0.f, float(std::cos(theta_i)));
    const glm::vec3 mirrored(direct.x, 0.f, -direct.z);
    const int h0 = guide.histogram(p, SpecularChain::Refraction);
    const int h1 = guide.histogram(p, SpecularChain::ReflectionRefraction);
    REQUIRE(h0 >= 0);
    REQUIRE(h1 >= 0);
    // Bins are about 8.5° across: the mean of the drawn directions lies
    // within half a bin of the truth.
    CHECK(angle_degrees(mean_direction(guide, h0), direct) < 4.5);
    CHECK(angle_degrees(mean_direction(guide, h1), mirrored) < 4.5);
    // The bin holding the truth is the densest.
    CHECK(guide.bins_pdf(h0, direct) > 0.5f * guide.bins_pdf(h0, mean_direction(guide, h0)));
    CHECK(guide.bins_pdf(h0, mirrored) == 0.f);
    // Nothing outside reflects into a lone slab.
    CHECK(guide.histogram(p, SpecularChain::RefractionReflection) == -1);
    // The cell's lobe: the light straight in, aimed at Snell's direction far
    // closer than a bin, over the disc's image through the face (to first
    // order: across the plane of incidence its 5° shrink by 1/1.6, within it
    // by cos θ_o / (1.6 cos θ_i)), widened by the fit's margin. At the
    // cell's centre the model is at its surest; p lies at a corner of its
    // cell, where the noise of the fitted change across the cell (none in
    // a slab) counts most: 0.44° with this guide's 2^18 rays, 0.11° with
    // 2^22. The light after the floor's mirror has no lobe.
    const glm::vec3 centre(20.f / 24.f, 20.f / 24.f, 0.5f);  // cells are 40/24 wide from −20
    REQUIRE(guide.histogram(centre, SpecularChain::Refraction) == h0);
    const std::optional<EllipticCone> lobe = guide.lobe(h0, centre);
    REQUIRE(lobe);
    CHECK(angle_degrees(lobe->axis, direct) < 0.2);
    const std::optional<EllipticCone> corner = guide.lobe(h0, p);
    REQUIRE(corner);
    CHECK(angle_degrees(corner->axis, direct) < 1.0);
    const double disc = std::tan(5.0 * kPiD / 180.0), margin = DirectionFitSettings{}.margin;
    CHECK(lobe->r_major / margin == Approx(disc / 1.6).epsilon(0.05));
    CHECK(lobe->r_minor / margin == Approx(disc * std::cos(theta_o) / (1.6 * std::cos(theta_i))).epsilon(0.05));
    CHECK(std::abs(lobe->major.y) > 0.99f);  // across the plane of incidence (x, z)
    CHECK_FALSE(guide.lobe(h1, p));
}

TEST_CASE("beside a wall the guide points back along the beam the wall mirrors into the slab", "[light_guide]") {
    // A wall (x ≤ 0, up to z = 4) and a slab beside it (x ≥ 0.2, up to
    // z = 0.3), light 30° from the vertical on the slab's side. The beam
    // mirrored off the wall's face x = 0 travels (sin 30°, 0, −cos 30°) and
    // refracts into the slab's top: there it travels (sin θ_i, 0, −cos θ_i),
    // sin θ_i = sin 30° / 1.6, so toward the light by that chain is
    // (−sin θ_i, 0, cos θ_i). The light straight in comes the other way in x.
    const TriangleMesh mesh = jade_test::merged_mesh(jade_test::box_mesh({-1, -3, 0}, {0, 3, 4}),
                                        jade_test::box_mesh({0.2f, -3, 0}, {4, 3, 0.3f}));
    const MeshAccel accel(mesh, true);
    REQUIRE_FALSE(accel.convex());
    const HomogeneousMedium medium(Spectrum(0.5f), Spectrum(0.1f));
    const double theta = 30.0 * kPiD / 180.0, theta_i = std::asin(std::sin(theta) / 1.6);
    const Scene s = guide_scene(accel, medium, {float(std::sin(theta)), 0.f, float(std::cos(theta))}, 5.f);
    const LightGuide guide(s, 2);
    // The mirrored beam reaches the slab's top for x up to about
    // 3.7·tan 30° = 2.1: a point in the slab under it.
    const glm::vec3 p(1.f, 0.f, 0.15f);
    const int h2 = guide.histogram(p, SpecularChain::RefractionReflection);
    REQUIRE(h2 >= 0);
    const glm::vec3 truth(float(-std::sin(theta_i)), 0.f, float(std::cos(theta_i)));
    CHECK(angle_degrees(mean_direction(guide, h2), truth) < 4.5);
    const int h0 = guide.histogram(p, SpecularChain::Refraction);
    REQUIRE(h0 >= 0);
    CHECK(angle_degrees(mean_direction(guide, h0), {float(std::sin(theta_i)), 0.f, float(std::cos(theta_i))}) < 4.5);
    // The mirrored beam's edge: the wall's top (z = 4) mirrors the disc's
    // steepest rays (35° from the vertical) to x = 3.7·tan 35° = 2.59 on the
    // slab's top, and inside they move on by 0.3·tan θ_i < 0.1. Cells are
    // 0.25 wide from x = −1: the cell [2.75, 3) gets none of that light, but
    // its neighbour [2.5, 2.75) does, so its histogram is its neighbours',
    // pointing the same way. The next cell, [3, 3.25), is two cells from
    // the light's reach: none.
    const int beside = guide.histogram({2.85f, 0.f, 0.15f}, SpecularChain::RefractionReflection);
    REQUIRE(beside >= 0);
    CHECK(angle_degrees(mean_direction(guide, beside), truth) < 4.5);
    CHECK(guide.histogram({3.1f, 0.f, 0.15f}, SpecularChain::RefractionReflection) == -1);
}

TEST_CASE("the guide is a normalised density that the threads do not change and a delta light has none",
          "[light_guide]") {
    const TriangleMesh sphere = icosphere(4, 1.f);
    const MeshAccel accel(sphere);
    REQUIRE(accel.convex());
    const HomogeneousMedium medium(Spectrum(1.f), Spectrum(0.2f));
    const Scene s = guide_scene(accel, medium, {0.3f, 0.8f, 0.5f}, 10.f);
    const LightGuide guide(s, 3);
    LightGuide one_thread;
    tbb::task_arena(1).execute([&] { one_thread = LightGuide(s, 3); });
    SplitMix64 rng(5);
    int lobes = 0;
    for (const glm::vec3& p : {glm::vec3(0.f), glm::vec3(0.3f, 0.5f, 0.2f), glm::vec3(-0.4f, 0.1f, -0.3f)}) {
        for (SpecularChain chain : {SpecularChain::Refraction, SpecularChain::ReflectionRefraction}) {
            const int h = guide.histogram(p, chain);
            REQUIRE(h >= 0);
            REQUIRE(one_thread.histogram(p, chain) == h);
            // The density over the bins sums to 1, the directions drawn
            // fall in each bin as often as it says (binomial, 5 standard
            // deviations), and the guide built on one thread is the same.
            const SphereBins& bins = guide.bins();
            double total = 0.0;
            bool same = true;
            for (int b = 0; b < bins.count(); ++b) {
                const glm::vec3 centre = bins.direction(b, 0.5f, 0.5f);
                total += double(guide.bins_pdf(h, centre)) * bins.solid_angle();
                same = same && guide.bins_pdf(h, centre) == one_thread.bins_pdf(h, centre);
            }
            CHECK(total == Approx(1.0).epsilon(1e-4));
            CHECK(same);
            // The lobes' sums are integers too.
            const std::optional<EllipticCone> lobe = guide.lobe(h, p), alone = one_thread.lobe(h, p);
            REQUIRE(lobe.has_value() == alone.has_value());
            if (lobe) {
                ++lobes;
                CHECK((lobe->axis == alone->axis && lobe->r_major == alone->r_major &&
                       lobe->r_minor == alone->r_minor));
            }
            const int n = 200000;
            std::vector<int> counts(std::size_t(bins.count()), 0);
            for (int k = 0; k < n; ++k)
                ++counts[std::size_t(bins.index(guide.sample_bins(h, float(rng.uniform()), float(rng.uniform()),
                                                             float(rng.uniform()))))];
            double worst = 0.0;
            for (int b = 0; b < bins.count(); ++b) {
                const double q = double(guide.bins_pdf(h, bins.direction(b, 0.5f, 0.5f))) * bins.solid_angle();
                const double sd = std::sqrt(n * q * (1.0 - q)) + 1.0;
                worst = std::max(worst, std::abs(counts[std::size_t(b)] - n * q) / sd);
            }
            CHECK(worst < 5.0);
        }
        // A ray leaving a convex object meets nothing: no mirrored chain.
        CHECK(guide.histogram(p, SpecularChain::RefractionReflection) == -1);
    }
    CHECK(lobes == 3);  // one per vertex: the light straight in
    const Scene delta = guide_scene(accel, medium, {0.3f, 0.8f, 0.5f}, 0.f);
    CHECK(LightGuide(delta, 3).empty());
}

TEST_CASE("the guide's rays follow the render's camera samples: one per 64 between 2^18 and 2^20 and at most one per 4",
          "[light-guide]") {
    CHECK(light_guide_photons(128.0 * 128.0 * 256.0) == 1u << 18);  // a fitting render: the fewest
    CHECK(light_guide_photons(256.0 * 256.0 * 512.0) == 1u << 19);
    CHECK(light_guide_photons(512.0 * 512.0 * 256.0) == 1u << 20);  // the demo's final render
    CHECK(light_guide_photons(4096.0 * 4096.0 * 1e6) == 1u << 20);  // a time-limited render's cap
    // A small render: at most one ray per 4 camera samples, never below 2^12.
    CHECK(light_guide_photons(64.0 * 64.0 * 256.0) == 1u << 18);
    CHECK(light_guide_photons(32.0 * 32.0 * 256.0) == 1u << 16);
    CHECK(light_guide_photons(24.0 * 20.0 * 37.0) == 4440u);
    CHECK(light_guide_photons(0.0) == 1u << 12);
}

TEST_CASE("a guide traced before and given to a render makes the image of the render that traces its own",
          "[light-guide]") {
    // The fit's renders share one guide (fit/fit_session.h): the render
    // given it must be the render that traces it, sample for sample. A box
    // behind the split boundary under a 10-degree disc.
    const MeshAccel accel(jade_test::box_mesh({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    const HomogeneousMedium medium(Spectrum(3.f, 2.f, 1.f), Spectrum(0.2f, 0.3f, 0.4f));
    const Scene scene = guide_scene(accel, medium, {0.3f, 0.8f, 0.5f}, 10.f);
    CameraParams params;
    params.origin = {0.5f, 1.f, 5.f};
    params.width = params.height = 24;
    const PinholeCamera camera(params);
    RenderSettings settings;
    settings.spp = 16;
    const RenderResult own = render(scene, camera, settings);
    IntegratorSettings traced = settings.integrator;
    traced.light_guide_photons = light_guide_photons(24.0 * 24.0 * 16.0);
    const std::shared_ptr<const LightGuide> guide = light_guide_for(scene, traced, settings.seed);
    REQUIRE(guide);
    RenderSettings given = settings;
    given.integrator.built_light_guide = guide;
    const RenderResult shared = render(scene, camera, given);
    CHECK(own.film.rgba(true) == shared.film.rgba(true));
    // And the guide is used as given: one traced from other rays makes
    // another image.
    traced.light_guide_photons /= 2;
    given.integrator.built_light_guide = light_guide_for(scene, traced, settings.seed);
    CHECK(render(scene, camera, given).film.rgba(true) != own.film.rgba(true));
}
