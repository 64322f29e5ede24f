// The one-refraction specular manifold against optics and geometry that are
// not the solver's own: Snell's solid-angle law at a flat surface, the
// refraction point on an exact sphere (found by scanning its great circle),
// and the Jacobian against finite differences of traced exits.

#include "jade/geometry/mesh_accel.h"
#include "jade/render/specular_manifold.h"
#include "jade/render/light.h"
#include "jade/render/light_estimators/manifold.h"
#include "jade/render/media/homogeneous.h"
#include "jade/core/random.h"
#include "jade/core/math.h"
#include "jade/core/sampling.h"
#include "jade/geometry/mesh_io.h"
#include "jade/render/tracking.h"

#include "support/render_test_util.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>

using namespace jade;

namespace {

Scene glass(const MeshAccel& accel, BoundaryMode mode = BoundaryMode::Split) {
    Scene s;
    s.boundary = &accel;
    s.interface.mode = mode;
    s.fit_ray_epsilon();
    return s;
}

glm::vec3 random_direction(SampleStream& rng) {
    const float z = 2.f * rng.uniform() - 1.f, phi = 6.2831853f * rng.uniform();
    const float s = std::sqrt(std::max(0.f, 1.f - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

// The exterior direction of interior direction w leaving an exact sphere
// of radius 1 at the origin from p (double precision, Snell's law).
bool sphere_exit(glm::dvec3 p, glm::dvec3 w, double ior, glm::dvec3& y, glm::dvec3& out) {
    const double b = glm::dot(p, w), c = glm::dot(p, p) - 1.0;
    const double t = -b + std::sqrt(b * b - c);
    y = p + t * w;
    const glm::dvec3 n = -y;  // facing the inside, where w comes from
    const double ci = -glm::dot(w, n), eta = 1.0 / ior;
    const double s2 = (1 - ci * ci) / (eta * eta);
    if (s2 >= 1) return false;
    out = w / eta + (ci / eta - std::sqrt(1 - s2)) * n;
    return true;
}

// |dω_out/dw| of the exact sphere by central differences in double.
double sphere_jacobian(glm::dvec3 p, glm::dvec3 w, double ior) {
    glm::dvec3 b1, b2;
    {
        glm::vec3 f1, f2;
        orthonormal_basis(glm::vec3(w), f1, f2);
        b1 = glm::dvec3(f1);
        b2 = glm::dvec3(f2);
        b1 = glm::normalize(b1 - w * glm::dot(w, b1));
        b2 = glm::normalize(glm::cross(w, b1));
    }
    const double h = 1e-5;
    glm::dvec3 y, o[4];
    const glm::dvec3 ws[4] = {glm::normalize(w + h * b1), glm::normalize(w - h * b1),
                              glm::normalize(w + h * b2), glm::normalize(w - h * b2)};
    for (int k = 0; k < 4; ++k)
        if (!sphere_exit(p, ws[k], ior, y, o[k])) return 0;
    const glm::dvec3 d1 = (o[0] - o[1]) / (2 * h), d2 = (o[2] - o[3]) / (2 * h);
    return glm::length(glm::cross(d1, d2));  // the interior side's is 1 by construction
}

// The exact sphere's exit point toward target ω from p: it lies on the
// great circle through p and ω (incident ray, normal and refracted ray are
// coplanar, and the normal passes through the centre). Scanned, then
// refined by golden-section search on the residual.
bool sphere_solution(glm::dvec3 p, glm::dvec3 target, double ior, glm::dvec3& y_best) {
    const glm::dvec3 e1 = glm::normalize(target);
    const glm::dvec3 e2 = glm::normalize(p - e1 * glm::dot(p, e1));
    auto residual = [&](double th, glm::dvec3& y) {
        const glm::dvec3 q = std::cos(th) * e1 + std::sin(th) * e2;
        glm::dvec3 out;
        if (!sphere_exit(p, glm::normalize(q - p), ior, y, out)) return 1e9;
        return glm::length(out - e1);
    };
    const int n = 20000;
    double best = 1e9, th_best = 0;
    glm::dvec3 y;
    for (int i = 0; i < n; ++i) {
        const double th = 2 * 3.14159265358979 * i / n;
        const double r = residual(th, y);
        if (r < best) best = r, th_best = th;
    }
    double a = th_best - 2 * 3.14159265358979 / n, b = th_best + 2 * 3.14159265358979 / n;
    for (int it = 0; it < 100; ++it) {
        const double c = b - 0.618033988749895 * (b - a), d = a + 0.618033988749895 * (b - a);
        glm::dvec3 yc, yd;
        if (residual(c, yc) < residual(d, yd)) b = d; else a = c;
    }
    const double r = residual(0.5 * (a + b), y_best);
    return r < 1e-9;
}

}  // namespace

TEST_CASE("the solver finds the exact sphere's refraction point and Jacobian", "[manifold]") {
    // The mesh is a 81 920-triangle sphere with exact vertex normals,
    // interpolated; the truth is the exact sphere's. From a point near the
    // surface the far side is seen beyond the critical angle, so some
    // directions have no refraction path at all: there the solver must fail.
    const TriangleMesh mesh = icosphere(6, 1.f);
    const MeshAccel accel(mesh);
    const Scene s = glass(accel);
    SampleStream rng(3, 0, 0);
    PathCounters counters;
    int reachable = 0, solved = 0, phantom = 0;
    const int trials = 400;
    for (int i = 0; i < trials; ++i) {
        const glm::vec3 p = 0.8f * std::cbrt(rng.uniform()) * random_direction(rng);
        const glm::vec3 target = random_direction(rng);
        glm::dvec3 y_true;
        const bool exists = sphere_solution(p, target, 1.6, y_true);
        const auto e = solve_refracted_exit(s, p, target, counters);
        reachable += exists;
        if (!exists) {
            phantom += bool(e);
            continue;
        }
        if (!e) continue;
        ++solved;
        const glm::dvec3 y = glm::dvec3(p) + double(e->hit.t) * glm::dvec3(e->direction);
        INFO("p " << p.x << " " << p.y << " " << p.z << ", target " << target.x << " " << target.y
                  << " " << target.z);
        CHECK(glm::length(e->exterior - target) < kManifoldTolerance);
        CHECK(glm::length(y - y_true) < 2e-3);
        CHECK(e->jacobian ==
              Approx(sphere_jacobian(p, glm::normalize(y_true - glm::dvec3(p)), 1.6)).epsilon(0.02));
    }
    INFO(reachable << " reachable, " << solved << " solved, " << phantom << " phantom");
    CHECK(reachable > trials / 2);
    CHECK(solved >= reachable * 99 / 100);  // 338 of 338 measured
    // Where the exact sphere has none, the mesh may have one only within
    // its faceting of the critical angle.
    CHECK(phantom <= trials / 100);
    CHECK(counters.manifold_walks == std::uint64_t(trials));
}

TEST_CASE("the exit Jacobian matches finite differences of traced exits", "[manifold]") {
    // Any mesh: on the cow, perturb the interior direction and measure the
    // exterior solid angle its image spans.
    const TriangleMesh cow = load_mesh(JADE_DATA_DIR "/meshes/spot-cow.obj");
    const MeshAccel accel(cow);
    const Scene s = glass(accel, BoundaryMode::Fresnel);
    const Cube cube = bounding_cube(cow);
    const glm::vec3 centre = glm::vec3(cube.min[0], cube.min[1], cube.min[2]) + 0.5f * float(cube.side);
    SampleStream rng(5, 0, 0);
    int checked = 0;
    for (int i = 0; i < 400 && checked < 100; ++i) {
        const glm::vec3 w = random_direction(rng);
        const auto e = refracted_exit(s, centre, w);
        if (!e || e->jacobian > 50.f) continue;  // near grazing, differences are meaningless
        glm::vec3 b1, b2;
        orthonormal_basis(w, b1, b2);
        const float h = 2e-4f;
        const auto e1 = refracted_exit(s, centre, glm::normalize(w + h * b1));
        const auto e2 = refracted_exit(s, centre, glm::normalize(w + h * b2));
        if (!e1 || !e2 || e1->hit.primitive != e->hit.primitive || e2->hit.primitive != e->hit.primitive)
            continue;
        const float fd = glm::length(glm::cross(e1->exterior - e->exterior, e2->exterior - e->exterior)) /
                         (h * h);
        CHECK(e->jacobian == Approx(fd).epsilon(0.03));
        ++checked;
    }
    CHECK(checked >= 60);
}

TEST_CASE("at a flat surface the Jacobian is Snell's solid-angle law", "[manifold]") {
    // n_i² cos θ_i dω_i = n_t² cos θ_t dω_t (radiance invariance of L / n²).
    const TriangleMesh slab = jade_test::box_mesh({-50, -50, 0}, {50, 50, 1});
    const MeshAccel accel(slab, true);
    const Scene s = glass(accel);
    for (float deg : {0.f, 10.f, 25.f, 35.f}) {
        const float th = radians(deg);
        const glm::vec3 w(std::sin(th), 0.f, std::cos(th));
        const auto e = refracted_exit(s, {0.3f, -0.2f, 0.4f}, w);
        REQUIRE(e);
        const double cos_t = e->exterior.z, n = 1.6;
        INFO("interior angle " << deg);
        CHECK(std::sin(std::acos(cos_t)) == Approx(n * std::sin(th)).margin(1e-5));
        CHECK(e->jacobian == Approx(n * n * std::cos(th) / cos_t).epsilon(1e-4));
        CHECK(e->transmission == Approx(0.5f));
    }
    // Beyond the critical angle (38.7°) nothing leaves.
    const float th = radians(40.f);
    CHECK(!refracted_exit(s, {0, 0, 0.5f}, glm::vec3(std::sin(th), 0.f, std::cos(th))));
    // The solver inverts the map: from a target exterior direction back to
    // the interior one, exactly on a flat surface.
    PathCounters counters;
    const glm::vec3 target = glm::normalize(glm::vec3(0.5f, -0.3f, 0.8f));
    const auto solved = solve_refracted_exit(s, {1.f, 2.f, 0.3f}, target, counters);
    REQUIRE(solved);
    CHECK(glm::length(solved->exterior - target) < kManifoldTolerance);
}

// --- Two vertices: an internal reflection, then the refraction out ---------

namespace {

// The exact sphere's chain (radius 1, origin): from p along w to y1, mirror
// reflection about the sphere's normal, on to y2, refracted out (double).
bool sphere_chain(glm::dvec3 p, glm::dvec3 w, double ior, glm::dvec3& out) {
    const auto hit = [](glm::dvec3 o, glm::dvec3 d) {
        const double b = glm::dot(o, d), c = glm::dot(o, o) - 1.0;
        return o + (-b + std::sqrt(std::max(0.0, b * b - c))) * d;
    };
    const glm::dvec3 y1 = hit(p, w);
    const glm::dvec3 d = w - 2.0 * glm::dot(w, y1) * y1;
    glm::dvec3 y2;
    return sphere_exit(y1, d, ior, y2, out);
}

double sphere_chain_jacobian(glm::dvec3 p, glm::dvec3 w, double ior) {
    glm::vec3 f1, f2;
    orthonormal_basis(glm::vec3(w), f1, f2);
    glm::dvec3 b1 = glm::normalize(glm::dvec3(f1) - w * glm::dot(w, glm::dvec3(f1)));
    glm::dvec3 b2 = glm::normalize(glm::cross(w, b1));
    const double h = 1e-5;
    glm::dvec3 o[4];
    const glm::dvec3 ws[4] = {glm::normalize(w + h * b1), glm::normalize(w - h * b1),
                              glm::normalize(w + h * b2), glm::normalize(w - h * b2)};
    for (int k = 0; k < 4; ++k)
        if (!sphere_chain(p, ws[k], ior, o[k])) return 0;
    return glm::length(glm::cross((o[0] - o[1]) / (2 * h), (o[2] - o[3]) / (2 * h)));
}

}  // namespace

TEST_CASE("a chain through a flat slab: a mirror then Snell and the solver finds it exactly", "[manifold]") {
    // Reflected off the slab's floor (z = 0) and refracted out of its top
    // (z = 1): a mirror keeps solid angle, so |dω/dw| is Snell's law for the
    // reflected direction, and the weight is the split's 0.5 × 0.5.
    const TriangleMesh slab = jade_test::box_mesh({-50, -50, 0}, {50, 50, 1});
    const MeshAccel accel(slab, true);
    const Scene s = glass(accel);
    const glm::vec3 p(0.3f, -0.2f, 0.4f);
    for (float deg : {5.f, 20.f, 35.f}) {
        const float th = radians(deg);
        const glm::vec3 w(std::sin(th) * 0.6f, std::sin(th) * 0.8f, -std::cos(th));
        const auto e = reflected_exit(s, p, w);
        REQUIRE(e);
        INFO("interior angle " << deg);
        CHECK(e->reflection_point.z == Approx(0.f).margin(1e-5));
        CHECK(e->exit_point.z == Approx(1.f).margin(1e-5));
        const double cos_t = e->exterior.z, n = 1.6;
        CHECK(std::sin(std::acos(cos_t)) == Approx(n * std::sin(th)).margin(1e-5));
        CHECK(e->jacobian == Approx(n * n * std::cos(th) / cos_t).epsilon(1e-4));
        CHECK(e->weight == Approx(0.25f));
        PathCounters counters;
        const auto solved = solve_reflected_exit(s, p, e->exterior, counters);
        REQUIRE(solved);
        CHECK(glm::length(solved->exterior - e->exterior) < kManifoldTolerance);
        CHECK(glm::length(solved->reflection_point - e->reflection_point) < 1e-3f);
    }
    // Beyond the critical angle the floor reflects everything (weight 1) but
    // the top reflects it back too: no exit.
    const float th = radians(40.f);
    CHECK(!reflected_exit(s, p, glm::vec3(std::sin(th), 0.f, -std::cos(th))));
}

TEST_CASE("the chain's Jacobian matches the exact sphere and finite differences on the cow", "[manifold]") {
    {
        // The 81 920-triangle sphere with exact vertex normals, interpolated,
        // against the exact sphere's chain differentiated in double.
        const TriangleMesh mesh = icosphere(6, 1.f);
        const MeshAccel accel(mesh);
        const Scene s = glass(accel);
        SampleStream rng(7, 0, 0);
        int checked = 0;
        for (int i = 0; i < 2000 && checked < 100; ++i) {
            const glm::vec3 p = 0.8f * std::cbrt(rng.uniform()) * random_direction(rng);
            const glm::vec3 w = random_direction(rng);
            const auto e = reflected_exit(s, p, w);
            // Within a few degrees of the critical angle at y2 (38.7°) the
            // exit turns fast enough that the facets' chords (and y1's
            // plane) shift it measurably: the mesh's own differences agree
            // there (below), the exact sphere's by up to 40 %; likewise near
            // the curved mirror's caustics, where |dω/dw| → 0.
            if (!e || !(glm::dot(e->reflected, e->exit.shading_normal) > std::cos(radians(34.f))) ||
                e->jacobian < 0.01f)
                continue;
            glm::dvec3 out;
            if (!sphere_chain(p, w, 1.6, out)) continue;
            CHECK(glm::length(glm::dvec3(e->exterior) - out) < 2e-3);
            CHECK(e->jacobian == Approx(sphere_chain_jacobian(p, w, 1.6)).epsilon(0.03));
            ++checked;
        }
        CHECK(checked >= 100);
    }
    // Any mesh: the cow, whose legs and ears reflect at every angle.
    const TriangleMesh cow = load_mesh(JADE_DATA_DIR "/meshes/spot-cow.obj");
    const MeshAccel accel(cow);
    const Scene s = glass(accel, BoundaryMode::Fresnel);
    const Cube cube = bounding_cube(cow);
    const glm::vec3 centre = glm::vec3(cube.min[0], cube.min[1], cube.min[2]) + 0.5f * float(cube.side);
    SampleStream rng(9, 0, 0);
    int checked = 0;
    for (int i = 0; i < 4000 && checked < 60; ++i) {
        const glm::vec3 w = random_direction(rng);
        const auto e = reflected_exit(s, centre, w);
        if (!e || e->jacobian > 50.f) continue;
        glm::vec3 b1, b2;
        orthonormal_basis(w, b1, b2);
        const float h = 2e-4f;
        const auto e1 = reflected_exit(s, centre, glm::normalize(w + h * b1));
        const auto e2 = reflected_exit(s, centre, glm::normalize(w + h * b2));
        if (!e1 || !e2 || e1->exit.primitive != e->exit.primitive || e2->exit.primitive != e->exit.primitive ||
            e1->reflection.primitive != e->reflection.primitive || e2->reflection.primitive != e->reflection.primitive)
            continue;
        const float fd = glm::length(glm::cross(e1->exterior - e->exterior, e2->exterior - e->exterior)) / (h * h);
        CHECK(e->jacobian == Approx(fd).epsilon(0.05));
        ++checked;
    }
    CHECK(checked >= 40);
}

TEST_CASE("the chain solver inverts traced chains", "[manifold]") {
    // From a vertex inside the object (the middle of a random line's first
    // stretch inside), trace a random direction's chain to its exterior
    // direction; the solver, given that direction, must find a chain
    // leaving along it (there may be several; any is right). How often it
    // does depends on the shape, and the bounds hold what was measured: its
    // seed is exact for flat walls; the sphere 300 of 300, the vase's thin
    // smooth walls 202 of 300; the bunny 26 and the cow 2, whose chains
    // cross ears, legs and folds far from the wall the seed mirrors in.
    struct Case {
        const char* name;
        TriangleMesh mesh;
        int at_least_percent;
    };
    const Case cases[] = {{"sphere", icosphere(6, 1.f), 95},
                          {"vase", load_mesh(JADE_DATA_DIR "/meshes/greek-vase-01.glb"), 50},
                          {"cow", load_mesh(JADE_DATA_DIR "/meshes/spot-cow.obj"), 0},
                          {"bunny", load_mesh(JADE_DATA_DIR "/meshes/stanford-bunny-watertight-70k.obj"), 5}};
    for (const Case& k : cases) {
        const MeshAccel accel(k.mesh);
        const Scene s = glass(accel);
        const Cube cube = bounding_cube(k.mesh);
        const glm::vec3 centre = glm::vec3(cube.min[0], cube.min[1], cube.min[2]) + 0.5f * float(cube.side);
        SampleStream rng(11, 0, 0);
        PathCounters counters;
        int traced = 0, solved = 0;
        for (int i = 0; i < 20000 && traced < 300; ++i) {
            const glm::vec3 d = random_direction(rng);
            const glm::vec3 from = centre - float(cube.side) * d;
            const auto in = accel.intersect(from, d, 0.f, 1e30f);
            if (!in) continue;
            const glm::vec3 entry = from + in->t * d;
            const auto out = accel.intersect(s.offset(entry, in->geometric_normal, d), d, 0.f, 1e30f);
            if (!out) continue;
            const glm::vec3 p = entry + 0.5f * out->t * d;
            const auto e = reflected_exit(s, p, random_direction(rng));
            if (!e) continue;
            ++traced;
            const auto found = solve_reflected_exit(s, p, e->exterior, counters);
            if (!found) continue;
            ++solved;
            CHECK(glm::length(found->exterior - e->exterior) < kManifoldTolerance);
        }
        INFO(k.name << ": " << traced << " traced, " << solved << " solved");
        CHECK(traced == 300);
        CHECK(solved * 100 >= traced * k.at_least_percent);
        CHECK(counters.manifold_walks == std::uint64_t(traced));
    }
}

TEST_CASE("a delta light's walk ended after its probe by roulette keeps the estimate's mean", "[manifold]") {
    // From a vertex deep in a sphere, the probe toward the light finds the
    // surface 1.6 away; with σ_t at least 1.2 the light that gets through is
    // at most e^(−1.92) = 0.147, below kProbeFullTransmittance, so the walk
    // goes on with probability 0.147 / 0.25 = 0.587 (exact sphere) and its
    // light is weighed by the inverse. The mean over many estimates is the
    // light of the walk itself (solve_refracted_exit: E · transmission /
    // |dω/dw|), to within the binomial count's standard error.
    const TriangleMesh mesh = icosphere(6, 1.f);
    const MeshAccel accel(mesh);
    const HomogeneousMedium medium(Spectrum(1.0f, 2.f, 3.f), Spectrum(0.2f, 0.3f, 0.4f));
    Scene s = jade_test::basic_scene(accel, &medium, BoundaryMode::Split, Spectrum(0.f));
    const glm::vec3 to_light(0.f, 0.f, 1.f);
    const DirectionalLight light(to_light, 3.f, 0.f);
    const ManifoldEstimator estimator(s, light, SpecularChain::Refraction);
    const glm::vec3 p(0.05f, -0.03f, -0.6f);

    const double expected_survival = std::exp(-1.2 * 1.6) / double(kProbeFullTransmittance);
    const auto seed = refraction_seed(s, p, to_light);
    REQUIRE(seed);
    CHECK(seed->probe_distance == Approx(std::sqrt(1.0 - 0.05 * 0.05 - 0.03 * 0.03) + 0.6).epsilon(1e-3));
    const float survival = probe_survival(s, seed->probe_distance);
    CHECK(survival == Approx(expected_survival).epsilon(0.01));

    PathCounters counters;
    const auto exit = solve_refracted_exit(s, p, to_light, counters);
    REQUIRE(exit);
    const double light_of_walk = 3.0 * double(exit->transmission) / double(exit->jacobian);

    SampleStream rng(11, 0, 0);
    const int n = 20000;
    double sum = 0.0;
    int went_on = 0;
    for (int i = 0; i < n; ++i) {
        const auto ls = estimator.sample(p, 0.5f, 0.5f, rng, counters);
        if (!ls || !(ls->radiance.x > 0.f)) continue;
        ++went_on;
        CHECK(double(ls->radiance.x) == Approx(light_of_walk / survival).epsilon(1e-5));
        sum += double(ls->radiance.x);
    }
    const double q = survival;
    INFO(went_on << " of " << n << " walks went on past the probe");
    CHECK(std::abs(sum / n - light_of_walk) < 5.0 * light_of_walk * std::sqrt((1.0 - q) / (q * n)));
    CHECK(counters.manifold_probes_ended + std::uint64_t(went_on) == std::uint64_t(n));
    // The same vertex's walk under a disc light is never ended: its density
    // would have to carry the survival into MIS.
    const DirectionalLight disc(to_light, 3.f, 1.f);
    const ManifoldEstimator disc_estimator(s, disc, SpecularChain::Refraction);
    PathCounters disc_counters;
    for (int i = 0; i < 100; ++i) (void)disc_estimator.sample(p, rng.uniform(), rng.uniform(), rng, disc_counters);
    CHECK(disc_counters.manifold_probes_ended == 0);
}
