// The reference scenes of data/reference/ (Mitsuba 3, volpathmis; see its
// README): our renders must agree with them in expectation. Each test renders
// at half or quarter resolution and compares with the reference averaged over
// the same pixels (box filter), block by block, with a tolerance from both
// images' per-pixel variance: |z| < 4.5 per 16x16 block and channel, |z| < 4
// for the whole image.

#include "jade/geometry/mesh_accel.h"
#include "jade/geometry/mesh_io.h"
#include "jade/geometry/sphere_boundary.h"
#include "jade/render/integrator.h"
#include "jade/render/media/grid.h"
#include "jade/render/media/homogeneous.h"
#include "jade/render/renderer.h"
#include "jade/io/vdb_io.h"

#include "support/render_test_util.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <random>

using namespace jade;

namespace {

const std::string kRef = JADE_DATA_DIR "/reference/";

PinholeCamera reference_camera(glm::vec3 origin, int size) {
    CameraParams p;
    p.origin = origin;
    p.target = glm::vec3(0.f);
    p.fov_degrees = 40.f;
    p.width = p.height = size;
    return PinholeCamera(p);
}

RenderResult render_reference_scene(const Boundary& boundary, const Medium& medium, BoundaryMode mode,
                                    glm::vec3 origin, int size, int spp) {
    Scene s;
    s.boundary = &boundary;
    s.medium = &medium;
    s.interface.mode = mode;
    s.interface.ior = 1.6f;
    s.environment = Environment(Spectrum(1.f));  // directional light off, as in the references
    s.fit_ray_epsilon();
    RenderSettings rs;
    rs.spp = spp;
    rs.seed = 2024;
    return render(s, reference_camera(origin, size), rs);
}

RenderResult render_reference_scene(const TriangleMesh& mesh, bool flat, const Medium& medium,
                                    BoundaryMode mode, glm::vec3 origin, int size, int spp) {
    const MeshAccel accel(mesh, flat);
    return render_reference_scene(accel, medium, mode, origin, size, spp);
}

// Pixels that the unit sphere's silhouette crosses, seen from (0, 0, 4) with
// the reference camera. Mitsuba rendered the analytic sphere; our
// icosphere's flat faces lie up to 2e-4 inside it, so a pixel the outline
// barely touches can be covered in one image and not the other. Interiors
// agree (the README measured 1e-4 on the image mean). With our analytic
// sphere too, the outline's grazing chords read brighter than Mitsuba's
// (by 0.0016 in blue at 256², half the icosphere's excess): the reference's
// own bias at the boundary (data/reference/README.md: blue 0.19 % low, from
// Mitsuba's ray offset) weighs most where the chords are shortest. The
// independent analog simulation agrees there.
bool on_sphere_outline(int x, int y, int size) {
    const double tan_half = std::tan(20.0 * 3.14159265358979323846 / 180.0);
    int inside = 0;
    for (int k = 0; k < 4; ++k) {
        const double fx = (x + (k & 1)) / double(size), fy = (y + (k >> 1)) / double(size);
        const glm::dvec3 d = glm::normalize(glm::dvec3((2 * fx - 1) * tan_half, (1 - 2 * fy) * tan_half, -1.0));
        // Distance from the centre to the ray from (0, 0, 4): |o x d|.
        inside += glm::length(glm::cross(glm::dvec3(0, 0, 4), d)) < 1.0;
    }
    return inside != 0 && inside != 4;
}

void check_against(const RenderResult& r, const std::string& scene, int factor, bool sphere_outline) {
    const ImageF32 ref = read_image_f32(kRef + scene + "_ref.exr");
    const ImageF32 var = read_image_f32(kRef + scene + "_var.exr");
    jade_test::Expected e = jade_test::downsampled(ref, var, factor);
    const int size = r.film.width();
    if (sphere_outline) e.skip = [size](int x, int y) { return on_sphere_outline(x, y, size); };
    const auto z = jade_test::block_z_scores(r.film, e, 16);
    INFO("scene " << scene << ": " << z);
    CHECK(z.max_abs_z < 4.5);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(z.whole_image_z[c]) < 4.0);
    CHECK(r.counters.capped_paths == 0);
}

// Scene A by the simplest estimator there is, written independently of the
// renderer: analog Monte Carlo (free flights with σ_t, absorption as path
// termination) in the analytic unit sphere, one channel at a time. With an
// index-matched boundary and a unit environment, a pixel's value is the
// probability that its photon escapes.
struct AnalogImage {
    std::vector<double> mean, var;  // per pixel and channel
};
AnalogImage analog_scene_a(int size, int spp) {
    const double sigma_t[3] = {4, 8, 12}, albedo[3] = {0.95, 0.9, 0.8};
    const double tan_half = std::tan(20.0 * 3.14159265358979323846 / 180.0);
    std::mt19937_64 gen(12345);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    AnalogImage img;
    img.mean.assign(std::size_t(size) * size * 3, 0.0);
    img.var.assign(img.mean.size(), 0.0);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c) {
                int escaped = 0;
                for (int s = 0; s < spp; ++s) {
                    const double fx = (x + u(gen)) / size, fy = (y + u(gen)) / size;
                    double d[3] = {(2 * fx - 1) * tan_half, (1 - 2 * fy) * tan_half, -1.0};
                    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                    for (double& v : d) v /= n;
                    // Camera at (0, 0, 4): does the ray meet the sphere?
                    const double b = 4 * d[2], disc = b * b - 15.0;
                    if (disc < 0) { ++escaped; continue; }
                    const double t0 = -b - std::sqrt(disc);
                    double p[3] = {t0 * d[0], t0 * d[1], 4 + t0 * d[2]};
                    for (;;) {
                        const double bb = p[0] * d[0] + p[1] * d[1] + p[2] * d[2];
                        const double cc = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1.0;
                        const double exit = -bb + std::sqrt(std::max(0.0, bb * bb - cc));
                        const double flight = -std::log(1.0 - u(gen)) / sigma_t[c];
                        if (flight >= exit) { ++escaped; break; }
                        for (int k = 0; k < 3; ++k) p[k] += flight * d[k];
                        if (u(gen) >= albedo[c]) break;  // absorbed
                        const double z = 1 - 2 * u(gen), r = std::sqrt(std::max(0.0, 1 - z * z));
                        const double phi = 2 * 3.14159265358979323846 * u(gen);
                        d[0] = r * std::cos(phi);
                        d[1] = r * std::sin(phi);
                        d[2] = z;
                    }
                }
                const double m = double(escaped) / spp;
                const std::size_t i = (std::size_t(y) * size + x) * 3 + c;
                img.mean[i] = m;
                img.var[i] = m * (1 - m) / (spp - 1);
            }
    return img;
}

// A render of scene A at size² against the analog simulation of 256
// photons a pixel, in every pixel.
void check_against_analog(const RenderResult& r, int size) {
    const AnalogImage analog = analog_scene_a(size, 256);
    jade_test::Expected e;
    e.width = e.height = size;
    e.value = [&](int x, int y, int c) { return analog.mean[(std::size_t(y) * size + x) * 3 + c]; };
    e.variance = [&](int x, int y, int c) { return analog.var[(std::size_t(y) * size + x) * 3 + c]; };
    const auto z = jade_test::block_z_scores(r.film, e, 16);
    INFO("vs analog simulation: " << z);
    CHECK(z.max_abs_z < 4.5);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(z.whole_image_z[c]) < 4.0);
}

}  // namespace

TEST_CASE("scene A: homogeneous sphere, index-matched boundary", "[reference][render]") {
    const TriangleMesh mesh = load_mesh(kRef + "unit_sphere.obj");
    const HomogeneousMedium medium(Spectrum(3.8f, 7.2f, 9.6f), Spectrum(0.2f, 0.8f, 2.4f));
    const int size = 64;
    const RenderResult r = render_reference_scene(mesh, false, medium, BoundaryMode::None, {0, 0, 4}, size, 256);

    // Against the independent analog simulation: must agree.
    check_against_analog(r, size);

    // And against Mitsuba's corrected image (emitter sampling off; see
    // data/reference/README.md): must agree too, away from the outline.
    check_against(r, "sceneA", 256 / size, true);
}

TEST_CASE("scene B: the same medium inside a dielectric sphere (Fresnel)", "[reference][render]") {
    const TriangleMesh mesh = load_mesh(kRef + "unit_sphere.obj");
    const HomogeneousMedium medium(Spectrum(3.8f, 7.2f, 9.6f), Spectrum(0.2f, 0.8f, 2.4f));
    const RenderResult r = render_reference_scene(mesh, false, medium, BoundaryMode::Fresnel, {0, 0, 4}, 128, 384);
    check_against(r, "sceneB", 2, true);
}

// The scenes as Mitsuba rendered them, with the analytic sphere
// (geometry/sphere_boundary.h). Scene A is held to the analog simulation in
// every pixel, the outline's included.
TEST_CASE("scenes A and B with the analytic sphere", "[reference][render]") {
    const SphereBoundary sphere({0.f, 0.f, 0.f}, 1.f);
    const HomogeneousMedium medium(Spectrum(3.8f, 7.2f, 9.6f), Spectrum(0.2f, 0.8f, 2.4f));
    SECTION("A, index-matched") {
        const int size = 64;
        const RenderResult r = render_reference_scene(sphere, medium, BoundaryMode::None, {0, 0, 4}, size, 256);
        check_against_analog(r, size);
        check_against(r, "sceneA", 256 / size, true);
    }
    SECTION("B, dielectric (Fresnel)") {
        const RenderResult r = render_reference_scene(sphere, medium, BoundaryMode::Fresnel, {0, 0, 4}, 128, 384);
        check_against(r, "sceneB", 2, true);
    }
}

TEST_CASE("scene C: heterogeneous RGB grid inside a flat-shaded dielectric blob", "[reference][render]") {
    const TriangleMesh mesh = load_mesh(kRef + "blob.obj");
    const FloatGridMedium medium(read_medium_vdb(kRef + "sceneC_medium.vdb", DensityConversion{}));
    // The grid spans the blob's bounding box with 64 voxels per axis.
    CHECK(medium.placement().size == std::array<int, 3>{64, 64, 64});
    const RenderResult r = render_reference_scene(mesh, true, medium, BoundaryMode::Fresnel, {0, 0, 2.4f}, 128, 384);
    check_against(r, "sceneC", 2, false);
}
