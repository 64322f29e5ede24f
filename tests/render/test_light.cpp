// Lights: the lat-long environment's orientation, the background's film
// mapping, and the directional light's disc (radiance, sampling, pdf).

#include "jade/render/light.h"
#include "jade/core/random.h"

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
    const double l = light.radiance_toward(dir);
    CHECK(l * kPi * std::sin(alpha) * std::sin(alpha) == Approx(3.0).epsilon(1e-5));
    CHECK(light.radiance_toward(-dir) == 0.f);
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
    CHECK(delta.radiance_toward(dir) == 0.f);
    CHECK_THROWS(DirectionalLight(glm::vec3(0.f), 1.f, 0.f));
    CHECK_THROWS(DirectionalLight(dir, 1.f, 60.f));
}
