#include "jade/render/light.h"

#include "jade/core/error.h"
#include "jade/core/math.h"
#include "jade/core/sampling.h"

#include <glm/geometric.hpp>

#include <cmath>

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

float DirectionalLight::radiance_toward(const glm::vec3& w) const {
    if (is_delta() || !on()) return 0.f;
    return glm::dot(w, direction_) >= cos_radius_ ? radiance_ : 0.f;
}

Environment::Environment(const Spectrum& constant) : constant_(constant) {
    if (!is_finite(constant) || constant.x < 0.f || constant.y < 0.f || constant.z < 0.f)
        throw Error("--env must be finite and non-negative");
}

Environment::Environment(ImageF32 latlong, float scale) : scale_(scale) {
    if (latlong.width < 2 || latlong.height < 1) throw Error("environment image is too small");
    if (!(scale >= 0.f) || !std::isfinite(scale)) throw Error("--env-scale must be non-negative");
    for (float v : latlong.pixels)
        if (v < 0.f) throw Error("environment image holds negative radiance");
    image_ = std::make_shared<const ImageF32>(std::move(latlong));
}

Spectrum Environment::radiance_toward(const glm::vec3& w) const {
    if (!image_) return constant_;
    const float u = 0.5f + std::atan2(w.x, -w.z) * (0.5f / kPi);
    const float v = std::acos(std::clamp(w.y, -1.f, 1.f)) / kPi;
    return scale_ * bilinear(*image_, u * float(image_->width), v * float(image_->height), true);
}

Background::Background(ImageF32 image) : image_(std::move(image)) {
    if (image_.width < 1 || image_.height < 1) throw Error("background image has no pixels");
}

Spectrum Background::at(float x, float y) const {
    return bilinear(image_, x * float(image_.width), y * float(image_.height), false);
}

}  // namespace jade
