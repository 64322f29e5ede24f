// Lights: the lat-long environment's orientation and importance sampling,
// the background's film mapping, and the directional light's disc
// (radiance, sampling, pdf).

#include "jade/render/light.h"
#include "jade/core/random.h"

#include "support/render_test_util.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>

using namespace jade;

namespace {
constexpr double kPi = 3.14159265358979323846;

// An image whose red channel is the pixel's column and green its row.
ImageF32 coordinate_image(int w, int h) {
    ImageF32 img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            img.pixels.push_back(float(x));
            img.pixels.push_back(float(y));
            img.pixels.push_back(1.f);
        }
    return img;
}
}  // namespace

TEST_CASE("lat-long environment: +y at the top, -z at the centre, +x a quarter to the right", "[light]") {
    const Environment env(coordinate_image(64, 32), 2.f);
    // Looking along -z: u = 0.5, v = 0.5, i.e. continuous pixel (32, 16), between columns 31 and 32.
    const Spectrum c = env.radiance_toward({0, 0, -1});
    CHECK(c.x == Approx(2.f * 31.5f));
    CHECK(c.y == Approx(2.f * 15.5f));
    CHECK(c.z == Approx(2.f));
    CHECK(env.radiance_toward({1, 0, 0}).x == Approx(2.f * 47.5f));  // u = 0.75
    CHECK(env.radiance_toward({0, 1, 0}).y == Approx(0.f));          // top row
    CHECK(env.radiance_toward({0, -1, 0}).y == Approx(2.f * 31.f));  // bottom row
    CHECK_FALSE(env.black());
    CHECK(Environment(Spectrum(0.f)).black());
    CHECK(Environment(Spectrum(0.2f, 0.3f, 0.4f)).radiance_toward({0, 0, 1}) == Spectrum(0.2f, 0.3f, 0.4f));
    CHECK_THROWS(Environment(Spectrum(-1.f)));
}

TEST_CASE("the background is stretched over the film", "[light]") {
    const Background bg(coordinate_image(10, 20));
    CHECK(bg.at(0.05f, 0.025f).x == Approx(0.f));  // centre of pixel (0, 0)
    CHECK(bg.at(0.05f, 0.025f).y == Approx(0.f));
    CHECK(bg.at(0.95f, 0.975f).x == Approx(9.f));
    CHECK(bg.at(0.95f, 0.975f).y == Approx(19.f));
    CHECK(bg.at(0.5f, 0.5f).x == Approx(4.5f));
}

TEST_CASE("the directional light's disc gives its irradiance and is sampled uniformly", "[light]") {
    const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, 1.f, 0.2f));
    const DirectionalLight light(dir, 3.f, 10.f);
    const double alpha = 10.0 * kPi / 180.0;
    // Irradiance on a surface facing the light: ∫ L cos θ dω over the disc = L π sin² α = E.
    const double l = light.radiance_toward(dir).x;
    CHECK(l * kPi * std::sin(alpha) * std::sin(alpha) == Approx(3.0).epsilon(1e-5));
    CHECK(light.radiance_toward(-dir) == Spectrum(0.f));
    SampleStream rng(1, 2, 3);
    double sum_cos = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        float pdf;
        const float u1 = rng.uniform(), u2 = rng.uniform();
        const glm::vec3 w = light.disc().sample(u1, u2, pdf);
        REQUIRE(glm::dot(w, dir) >= std::cos(alpha) - 1e-6);
        REQUIRE(pdf == Approx(1.0 / (2 * kPi * (1 - std::cos(alpha)))).epsilon(1e-4));
        sum_cos += glm::dot(w, dir);
    }
    // Uniform over the cap: E[cos θ] = (1 + cos α) / 2.
    CHECK(sum_cos / n == Approx((1 + std::cos(alpha)) / 2).epsilon(1e-4));
    CHECK(light.disc().pdf(dir) == Approx(1.0 / (2 * kPi * (1 - std::cos(alpha)))).epsilon(1e-4));
    CHECK(light.disc().pdf(-dir) == 0.f);
    const DirectionalLight delta(dir, 2.f, 0.f);
    CHECK(delta.is_delta());
    CHECK(delta.disc().is_delta());
    CHECK(delta.disc().pdf(dir) == 0.f);
    CHECK(delta.radiance_toward(dir) == Spectrum(0.f));
    CHECK(delta.sample(0.3f, 0.7f).pdf == 0.f);
    CHECK(delta.sample(0.3f, 0.7f).radiance == Spectrum(2.f));  // its irradiance
    CHECK_THROWS(DirectionalLight(glm::vec3(0.f), 1.f, 0.f));
    CHECK_THROWS(DirectionalLight(dir, 1.f, 60.f));
}

namespace {
// Midpoint quadrature over the sphere in (θ, φ), fine enough to resolve
// every texel: calls f(w, dω) for each cell.
template <class F>
void sphere_quadrature(int n_theta, F&& f) {
    const int n_phi = 2 * n_theta;
    for (int i = 0; i < n_theta; ++i) {
        const double theta = (i + 0.5) * kPi / n_theta;
        const double d_omega = std::sin(theta) * (kPi / n_theta) * (2 * kPi / n_phi);
        for (int j = 0; j < n_phi; ++j) {
            const double phi = (j + 0.5) * 2 * kPi / n_phi;
            f(glm::vec3(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                        float(std::sin(theta) * std::sin(phi))),
              d_omega);
        }
    }
}
}  // namespace

TEST_CASE("environment importance sampling: a density over the sphere that follows the sky's brightness",
          "[light]") {
    const Environment env(jade_test::sun_and_sky_image(2, 1e4f), 0.5f);
    CHECK(env.negative_texels() == 2);
    CHECK(env.most_negative() == -0.004f);
    CHECK(!env.is_delta());

    // Quadrature (independent of the sampler): the density integrates to 1,
    // every direction of non-zero radiance has a non-zero density (the
    // bilinear lookup reaches into a texel's neighbours), and the sky's
    // integral ∫ L dω and ∫ L² dω per channel.
    double total_pdf = 0;
    glm::dvec3 integral(0.0), integral_sq(0.0);
    long uncovered = 0;
    sphere_quadrature(1024, [&](const glm::vec3& w, double d_omega) {
        const float pdf = env.pdf(w);
        const Spectrum L = env.radiance_toward(w);
        total_pdf += pdf * d_omega;
        if (max_component(L) > 0.f && !(pdf > 0.f)) ++uncovered;
        integral += glm::dvec3(L) * d_omega;
        integral_sq += glm::dvec3(L) * glm::dvec3(L) * d_omega;
    });
    CHECK(total_pdf == Approx(1.0).epsilon(2e-3));
    CHECK(uncovered == 0);

    // Sampling: each sample's density is pdf() of its direction, its
    // radiance the lookup's; E[L / pdf] is the integral, within 4.5 standard
    // errors of the estimate itself.
    SampleStream rng(7, 8, 9);
    const int n = 200000;
    glm::dvec3 sum(0.0), sum_sq(0.0);
    for (int i = 0; i < n; ++i) {
        const float u1 = rng.uniform(), u2 = rng.uniform();
        const DistantSample ds = env.sample(u1, u2);
        REQUIRE(ds.pdf > 0.f);
        REQUIRE(std::abs(glm::length(ds.direction) - 1.f) < 1e-5f);
        REQUIRE(ds.pdf == env.pdf(ds.direction));
        REQUIRE(ds.radiance == env.radiance_toward(ds.direction));
        const glm::dvec3 x = glm::dvec3(ds.radiance) / double(ds.pdf);
        sum += x;
        sum_sq += x * x;
    }
    for (int c = 0; c < 3; ++c) {
        const double mean = sum[c] / n, var = sum_sq[c] / n - mean * mean;
        INFO("channel " << c << ": estimate " << mean << ", quadrature " << integral[c]);
        CHECK(std::abs(mean - integral[c]) < 4.5 * std::sqrt(var / n) + 1e-3 * integral[c]);
        // And it is worth it: the variance per sample is far below uniform
        // sampling's, 4π ∫ L² dω − (∫ L dω)², which the sun dominates.
        const double uniform_var = 4 * kPi * integral_sq[c] - integral[c] * integral[c];
        CHECK(var * 50 < uniform_var);
    }
}

TEST_CASE("an environment image with NaN or infinite texels is refused and a constant one is sampled uniformly",
          "[light]") {
    ImageF32 img = jade_test::sun_and_sky_image(2, 1e4f);
    img.pixels[100] = std::nanf("");
    CHECK_THROWS_WITH(Environment(img), Catch::Contains("NaN or infinite"));
    img.pixels[100] = INFINITY;
    CHECK_THROWS(Environment(img));
    const Environment constant(Spectrum(0.2f, 0.3f, 0.4f));
    const DistantSample ds = constant.sample(0.3f, 0.6f);
    CHECK(ds.pdf == Approx(1.0 / (4 * kPi)));
    CHECK(constant.pdf(ds.direction) == Approx(1.0 / (4 * kPi)));
    CHECK(ds.radiance == Spectrum(0.2f, 0.3f, 0.4f));
    CHECK(Environment(jade_test::sun_and_sky_image(2, 1e4f), 0.f).black());
}
