#pragma once
// The scene's light (paper §5.3, §6; docs/design.md, "Lights"): one white directional light,
// an environment ("global illumination") seen by every ray that leaves the
// scene, and a background image seen by camera rays that miss the object.
//
// Directions are world directions; the environment's lat-long image maps
// direction d to u = 0.5 + atan2(d.x, −d.z) / 2π (across), v = acos(d.y) / π
// (down): +y is up, the image centre looks along −z, +x a quarter to the right.

#include "jade/core/distribution.h"
#include "jade/core/sampling.h"
#include "jade/io/image_io.h"
#include "jade/core/spectrum.h"

#include <glm/vec3.hpp>

#include <memory>
#include <string>

namespace jade {

// A direction toward a light at infinity and what arrives along it: `pdf` is
// its solid-angle density. A delta light's is 0 and its `radiance` is then
// its irradiance (the integral over the delta); any other light's pdf 0
// means no direction was drawn (radiance 0).
struct DistantSample {
    glm::vec3 direction{0.f};
    float pdf = 0.f;
    Spectrum radiance{0.f};
};

// What every light at infinity offers the light estimators
// (render/light_estimator.h): its radiance per direction, and directions
// drawn toward it with their density.
class DistantLight {
public:
    virtual ~DistantLight() = default;
    virtual bool is_delta() const = 0;
    // Radiance seen along propagation direction −w, i.e. looking toward w
    // (unit); 0 for a delta light.
    virtual Spectrum radiance_toward(const glm::vec3& w) const = 0;
    // u1, u2 uniform in [0, 1).
    virtual DistantSample sample(float u1, float u2) const = 0;
    virtual float pdf(const glm::vec3& w) const = 0;  // 0 for a delta light
};

// A distant light of irradiance `irradiance` on a surface facing it. With an
// angular radius α > 0 it is a disc of uniform radiance E / (π sin²α) around
// `direction` (the sun is α ≈ 0.27°); with α = 0 it is a delta light.
class DirectionalLight final : public DistantLight {
public:
    DirectionalLight() = default;  // off
    // direction points from the scene toward the light (need not be unit).
    DirectionalLight(const glm::vec3& direction, float irradiance, float angular_radius_degrees);

    bool on() const { return irradiance_ > 0.f; }
    bool is_delta() const override { return cos_radius_ >= 1.f; }
    const glm::vec3& direction() const { return direction_; }
    float irradiance() const { return irradiance_; }
    float angular_radius_degrees() const { return radius_degrees_; }
    Spectrum radiance_toward(const glm::vec3& w) const override;
    // Uniform over the disc; its radiance is returned without re-testing the
    // direction against the disc's edge, where rounding could drop a sample.
    DistantSample sample(float u1, float u2) const override;
    float pdf(const glm::vec3& w) const override { return disc().pdf(w); }
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
// or a lat-long (equirectangular) image, looked up bilinearly. An image's
// directions are importance-sampled in proportion to its brightness times
// sin θ (the texels' solid angle), so that a small bright sun in an HDR sky is
// found by the light estimators instead of by chance (docs/design.md,
// "Environment sampling"); a constant colour is sampled uniformly.
class Environment final : public DistantLight {
public:
    explicit Environment(const Spectrum& constant = Spectrum(0.f));
    // Throws for an unusable image (too small, NaN or infinite texels).
    // Negative texels, common in real HDRs as ringing around a bright sun,
    // read as 0: negative_texels() counts them for a warning.
    explicit Environment(ImageF32 latlong, float scale = 1.f);
    bool black() const { return !(scale_ > 0.f) || (!image_ && constant_ == Spectrum(0.f)); }
    bool is_image() const { return image_ != nullptr; }
    long negative_texels() const { return negative_texels_; }
    float most_negative() const { return most_negative_; }

    bool is_delta() const override { return false; }
    Spectrum radiance_toward(const glm::vec3& w) const override;
    DistantSample sample(float u1, float u2) const override;
    float pdf(const glm::vec3& w) const override;

private:
    Spectrum constant_{0.f};
    std::shared_ptr<const ImageF32> image_;
    std::shared_ptr<const PiecewiseConstant2D> distribution_;  // over the image's (u, v)
    float scale_ = 1.f;
    long negative_texels_ = 0;
    float most_negative_ = 0.f;
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
