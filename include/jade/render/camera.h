#pragma once
// Pinhole camera. The field of view is measured HORIZONTALLY (across the
// image's width), as in Mitsuba's default and the reference renders; the
// vertical extent follows from the aspect ratio. Film coordinates x, y in
// [0, 1], y pointing down (row 0 at the top):
//   direction ∝ forward + (2x − 1)·tan(fov/2)·right + (1 − 2y)·tan(fov/2)·(H/W)·up

#include "jade/geometry/mesh_io.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace jade {

struct CameraParams {
    glm::vec3 origin{0.f, 0.f, 4.f};
    glm::vec3 target{0.f};
    glm::vec3 up{0.f, 1.f, 0.f};
    float fov_degrees = 40.f;  // horizontal
    int width = 512;
    int height = 512;

    // Throws jade::Error for a zero-length view, up parallel to the view, or a
    // field of view outside (0, 180).
    void validate() const;
};

class PinholeCamera {
public:
    explicit PinholeCamera(const CameraParams& params);
    // Unit direction through film point (x, y) in [0,1]^2.
    glm::vec3 direction(float x, float y) const;
    // The film point (x, y) whose ray passes through p, if p lies in front
    // of the camera's plane: the inverse of direction(), unbounded (outside
    // [0, 1]² off the film).
    std::optional<glm::vec2> film_point(const glm::vec3& p) const;
    const glm::vec3& origin() const { return origin_; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    glm::vec3 origin_, forward_, right_, up_;
    float tan_half_x_, tan_half_y_;
    int width_, height_;
};

// A camera that frames a mesh: looking at its bounding-box centre from the
// upper front (+z, raised 20 degrees), far enough that the bounding sphere
// fits the narrower field of view with a 10% margin.
CameraParams frame_mesh(const Bounds3& bounds, int width, int height, float fov_degrees = 40.f);

// The camera of a scene file, for an image of width x height: glTF's
// vertical field of view becomes our horizontal one for that aspect ratio.
CameraParams camera_from_file(const FileCamera& camera, int width, int height);

}  // namespace jade
