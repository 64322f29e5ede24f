#pragma once
// The scene's light (paper §5.3, §6; docs/design.md, "Lights"): one white directional light,
// an environment ("global illumination") seen by every ray that leaves the
// scene, and a background image seen by camera rays that miss the object.
//
// Directions are world directions; the environment's lat-long image maps
// direction d to u = 0.5 + atan2(d.x, −d.z) / 2π (across), v = acos(d.y) / π
// (down): +y is up, the image centre looks along −z, +x a quarter to the right.

#include "jade/io/image_io.h"
#include "jade/core/sampling.h"
#include "jade/core/spectrum.h"

#include <glm/vec3.hpp>

#include <memory>
#include <string>

namespace jade {

// A distant light of irradiance `irradiance` on a surface facing it. With an
// angular radius α > 0 it is a disc of uniform radiance E / (π sin²α) around
// `direction` (the sun is α ≈ 0.27°); with α = 0 it is a delta light.
class DirectionalLight {
public:
    DirectionalLight() = default;  // off
    // direction points from the scene toward the light (need not be unit).
    DirectionalLight(const glm::vec3& direction, float irradiance, float angular_radius_degrees);

    bool on() const { return irradiance_ > 0.f; }
    bool is_delta() const { return cos_radius_ >= 1.f; }
    const glm::vec3& direction() const { return direction_; }
    float irradiance() const { return irradiance_; }
    float angular_radius_degrees() const { return radius_degrees_; }
    // Radiance seen along propagation direction -w, i.e. looking toward w (0 for a delta light).
    float radiance_toward(const glm::vec3& w) const;
    // The disc's uniform radiance (0 for a delta light): the value for
    // directions disc().sample() returns, without re-testing them against the disc's
    // edge, where rounding could drop a sample.
    float disc_radiance() const { return radiance_; }
    // The directions toward the light: its disc as a cone (a delta cone for a
    // delta light).
    UniformCone disc() const { return {direction_, cos_radius_}; }

private:
    glm::vec3 direction_{0.f, 1.f, 0.f};
    float irradiance_ = 0.f;
    float radius_degrees_ = 0.f;
    float cos_radius_ = 1.f;
    float radiance_ = 0.f;
};

// Radiance arriving from infinitely far in each direction: a constant colour,
// or a lat-long (equirectangular) image, looked up bilinearly.
class Environment {
public:
    explicit Environment(const Spectrum& constant = Spectrum(0.f));
    explicit Environment(ImageF32 latlong, float scale = 1.f);  // throws for an unusable image
    // Radiance looking toward direction w (unit).
    Spectrum radiance_toward(const glm::vec3& w) const;
    bool black() const { return !image_ && constant_ == Spectrum(0.f); }

private:
    Spectrum constant_{0.f};
    std::shared_ptr<const ImageF32> image_;
    float scale_ = 1.f;
};

// An image behind the object, stretched over the film: what a camera ray that
// misses sees at film position (x, y) in [0, 1]² instead of the environment.
class Background {
public:
    explicit Background(ImageF32 image);  // throws for an image without RGB
    Spectrum at(float x, float y) const;

private:
    ImageF32 image_;
};

}  // namespace jade
