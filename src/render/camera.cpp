#include "jade/render/camera.h"

#include "jade/core/error.h"
#include "jade/core/math.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace jade {

void CameraParams::validate() const {
    if (!(fov_degrees > 0.f && fov_degrees < 180.f))
        throw Error("--fov must lie strictly between 0 and 180 degrees");
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw Error("--width and --height must be between 1 and 16384 pixels");
    const glm::vec3 f = target - origin;
    if (!(glm::length(f) > 0.f)) throw Error("the camera's origin and target coincide");
    if (!(glm::length(glm::cross(f, up)) > 1e-6f * glm::length(f) * glm::length(up)))
        throw Error("the camera's up vector is parallel to its view direction (or zero)");
}

PinholeCamera::PinholeCamera(const CameraParams& p) : origin_(p.origin), width_(p.width), height_(p.height) {
    p.validate();
    forward_ = glm::normalize(p.target - p.origin);
    right_ = glm::normalize(glm::cross(forward_, p.up));
    up_ = glm::cross(right_, forward_);
    tan_half_x_ = std::tan(radians(0.5f * p.fov_degrees));
    tan_half_y_ = tan_half_x_ * float(p.height) / float(p.width);
}

glm::vec3 PinholeCamera::direction(float x, float y) const {
    return glm::normalize(forward_ + (2.f * x - 1.f) * tan_half_x_ * right_ +
                          (1.f - 2.f * y) * tan_half_y_ * up_);
}

std::optional<glm::vec2> PinholeCamera::film_point(const glm::vec3& p) const {
    const glm::vec3 q = p - origin_;
    const float z = glm::dot(q, forward_);
    if (!(z > 0.f)) return std::nullopt;
    return glm::vec2(0.5f * (glm::dot(q, right_) / (z * tan_half_x_) + 1.f),
                     0.5f * (1.f - glm::dot(q, up_) / (z * tan_half_y_)));
}

CameraParams frame_mesh(const Bounds3& b, int width, int height, float fov_degrees) {
    CameraParams p;
    p.width = width;
    p.height = height;
    p.fov_degrees = fov_degrees;
    p.target = b.centre();
    const float radius = 0.5f * glm::length(b.extent());
    const float tan_half_x = std::tan(radians(0.5f * fov_degrees));
    const float tan_half = std::min(tan_half_x, tan_half_x * float(height) / float(width));
    // The sphere fits when sin(half angle) * distance >= radius.
    const float half = std::atan(tan_half);
    const float distance = 1.1f * radius / std::sin(half);
    const float elevation = radians(20.f);
    p.origin = p.target + distance * glm::vec3(0.f, std::sin(elevation), std::cos(elevation));
    p.up = glm::vec3(0.f, 1.f, 0.f);
    return p;
}

CameraParams camera_from_file(const FileCamera& c, int width, int height) {
    CameraParams p;
    p.width = width;
    p.height = height;
    p.origin = c.origin;
    p.target = c.origin + c.forward;
    p.up = c.up;
    const float tan_half_x = std::tan(0.5f * c.yfov_radians) * float(width) / float(height);
    p.fov_degrees = degrees(2.f * std::atan(tan_half_x));
    return p;
}

}  // namespace jade
