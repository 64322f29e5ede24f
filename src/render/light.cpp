#include "jade/render/light.h"

#include "jade/core/error.h"
#include "jade/core/math.h"
#include "jade/core/sampling.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace jade {

namespace {
// Bilinear RGB lookup at continuous pixel coordinates (pixel centres at +½),
// wrapping across in x when `wrap_x`, clamped otherwise.
Spectrum bilinear(const ImageF32& img, float px, float py, bool wrap_x) {
    const float x = px - 0.5f, y = std::clamp(py - 0.5f, 0.f, float(img.height - 1));
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float fx = x - float(x0), fy = y - float(y0);
    auto col = [&](int xi) {
        if (wrap_x) return ((xi % img.width) + img.width) % img.width;
        return std::clamp(xi, 0, img.width - 1);
    };
    const int xa = col(x0), xb = col(x0 + 1);
    const int ya = std::clamp(y0, 0, img.height - 1), yb = std::min(ya + 1, img.height - 1);
    Spectrum s(0.f);
    const int nc = std::min(img.channels, 3);
    for (int c = 0; c < 3; ++c) {
        const int ch = c < nc ? c : 0;  // grey images fill all three channels
        s[c] = (1 - fy) * ((1 - fx) * img.at(xa, ya, ch) + fx * img.at(xb, ya, ch)) +
               fy * ((1 - fx) * img.at(xa, yb, ch) + fx * img.at(xb, yb, ch));
    }
    return s;
}
}  // namespace

DirectionalLight::DirectionalLight(const glm::vec3& direction, float irradiance,
                                   float angular_radius_degrees)
    : irradiance_(irradiance), radius_degrees_(angular_radius_degrees) {
    if (!(glm::length(direction) > 0.f) || !is_finite(direction))
        throw Error("--light-dir must be a non-zero direction");
    if (!(irradiance >= 0.f) || !std::isfinite(irradiance))
        throw Error("--light-irradiance must be finite and non-negative");
    if (!(angular_radius_degrees >= 0.f && angular_radius_degrees <= 45.f))
        throw Error("--light-radius must lie between 0 and 45 degrees");
    direction_ = glm::normalize(direction);
    const float alpha = radians(angular_radius_degrees);
    cos_radius_ = std::cos(alpha);
    if (alpha > 0.f) {
        const float s = std::sin(alpha);
        radiance_ = irradiance / (kPi * s * s);
    } else {
        cos_radius_ = 1.f;
    }
}

Spectrum DirectionalLight::radiance_toward(const glm::vec3& w) const {
    if (is_delta() || !on()) return Spectrum(0.f);
    return Spectrum(glm::dot(w, direction_) >= cos_radius_ ? radiance_ : 0.f);
}

DistantSample DirectionalLight::sample(float u1, float u2) const {
    DistantSample ds;
    ds.direction = disc().sample(u1, u2, ds.pdf);
    if (is_delta()) {
        ds.pdf = 0.f;
        ds.radiance = Spectrum(irradiance_);
    } else {
        ds.radiance = Spectrum(radiance_);
    }
    return ds;
}

namespace {
// The lat-long mapping (see the file's head): image coordinates in [0, 1)²
// of direction w, and back.
glm::vec2 latlong_uv(const glm::vec3& w) {
    return {0.5f + std::atan2(w.x, -w.z) * (0.5f / kPi),
            std::acos(std::clamp(w.y, -1.f, 1.f)) / kPi};
}

glm::vec3 latlong_direction(const glm::vec2& uv) {
    const float phi = 2.f * kPi * (uv.x - 0.5f), theta = kPi * uv.y;
    const float sin_theta = std::sin(theta);
    return {sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi)};
}

// A lat-long (u, v) density over the solid angle: dω = 2π² sin θ du dv.
// Directions within a hair of a pole are given the density a hair away
// (their radiance is finite, so the estimate there stays finite).
float solid_angle_pdf(float uv_pdf, float sin_theta) {
    return uv_pdf / (2.f * kPi * kPi * std::max(sin_theta, 1e-6f));
}

// Texel weights for importance sampling: the largest grey level (mean of
// the colour channels) of the texel and its eight neighbours (bilinear lookups reach that far, so
// every direction of non-zero radiance keeps a non-zero density) times the
// sine of the row's polar angle (the texels' solid angle).
std::vector<float> sampling_weights(const ImageF32& img) {
    const int w = img.width, h = img.height, nc = std::min(img.channels, 3);
    std::vector<float> mean(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float sum = 0.f;
            for (int c = 0; c < nc; ++c) sum += img.at(x, y, c);
            mean[std::size_t(y) * w + x] = sum / float(nc);
        }
    std::vector<float> weights(mean.size());
    for (int y = 0; y < h; ++y) {
        const float sin_theta = std::sin(kPi * (float(y) + 0.5f) / float(h));
        for (int x = 0; x < w; ++x) {
            float m = 0.f;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int yy = std::clamp(y + dy, 0, h - 1), xx = ((x + dx) % w + w) % w;
                    m = std::max(m, mean[std::size_t(yy) * w + xx]);
                }
            weights[std::size_t(y) * w + x] = m * sin_theta;
        }
    }
    return weights;
}
}  // namespace

Environment::Environment(const Spectrum& constant) : constant_(constant) {
    if (!is_finite(constant) || constant.x < 0.f || constant.y < 0.f || constant.z < 0.f)
        throw Error("--env must be finite and non-negative");
}

Environment::Environment(ImageF32 latlong, float scale) : scale_(scale) {
    if (latlong.width < 2 || latlong.height < 1) throw Error("environment image is too small");
    if (!(scale >= 0.f) || !std::isfinite(scale)) throw Error("--env-scale must be non-negative");
    for (float& v : latlong.pixels) {
        if (!std::isfinite(v)) throw Error("environment image holds NaN or infinite radiance");
        if (v < 0.f) {
            ++negative_texels_;
            most_negative_ = std::min(most_negative_, v);
            v = 0.f;
        }
    }
    distribution_ = std::make_shared<const PiecewiseConstant2D>(sampling_weights(latlong),
                                                                latlong.width, latlong.height);
    image_ = std::make_shared<const ImageF32>(std::move(latlong));
}

Spectrum Environment::radiance_toward(const glm::vec3& w) const {
    if (!image_) return constant_;
    const glm::vec2 uv = latlong_uv(w);
    return scale_ * bilinear(*image_, uv.x * float(image_->width), uv.y * float(image_->height), true);
}

DistantSample Environment::sample(float u1, float u2) const {
    DistantSample ds;
    if (!image_) {  // uniform over the sphere
        ds.direction = uniform_sphere(u1, u2);
        ds.pdf = 1.f / (4.f * kPi);
        ds.radiance = constant_;
        return ds;
    }
    float uv_pdf;
    ds.direction = latlong_direction(distribution_->sample(u1, u2, uv_pdf));
    // The density of the direction as pdf() gives it (rounding may carry a
    // direction on a texel's edge into its neighbour), so that MIS weighs
    // both strategies with one density; none (0) means no sample.
    ds.pdf = pdf(ds.direction);
    if (ds.pdf > 0.f) ds.radiance = radiance_toward(ds.direction);
    return ds;
}

float Environment::pdf(const glm::vec3& w) const {
    if (!image_) return 1.f / (4.f * kPi);
    const glm::vec2 uv = latlong_uv(w);
    return solid_angle_pdf(distribution_->pdf(uv), std::sqrt(std::max(0.f, 1.f - w.y * w.y)));
}

Background::Background(ImageF32 image) : image_(std::move(image)) {
    if (image_.width < 1 || image_.height < 1) throw Error("background image has no pixels");
}

Spectrum Background::at(float x, float y) const {
    return bilinear(image_, x * float(image_.width), y * float(image_.height), false);
}

}  // namespace jade
