#pragma once
// Light estimators: ways to find the directional light from a medium
// scattering vertex other than waiting for a phase-sampled path to hit it
// (docs/design.md, "Light estimators"). Each one samples a direction at the
// vertex toward the light and follows it there; the integrator weighs its
// estimate against phase sampling by multiple importance sampling (the
// balance heuristic) through the density of that direction.
//
// Variants live in render/light_estimators/:
//   shadow_ray      straight shadow rays through an index-matched boundary;
//                   it accounts for all the light (a delta light too)
//   refracted_cone  through a smooth dielectric: a cone aimed so that it
//                   refracts toward the light's disc, MIS-weighted against
//                   paths that leave by one refraction
//   manifold        through a smooth dielectric: a point of the light's disc
//                   (or the delta light's one direction), and the refraction
//                   path to it found by Newton's method on the surface
//                   (render/specular_manifold.h); MIS-weighted like the cone
// With none, the light is found only by paths that hit its disc.

#include "jade/core/random.h"
#include "jade/core/sampling.h"
#include "jade/core/spectrum.h"
#include "jade/render/tracking.h"

#include <glm/vec3.hpp>

#include <memory>
#include <optional>

namespace jade {

// How a phase-sampled path that meets the light by itself counts it.
enum class LightHits {
    Excluded,          // the estimator counts all of the light: hits count none
    WeightedOnExit,    // MIS against the estimator (its pdf()), for paths that leave the
                       // object by exactly one refraction after the scattering; others fully
};

// A sampled direction toward the light from a medium vertex and what
// arrives along it: the light's radiance times the boundary's transmission
// weight on the way, and the medium's transmittance. `pdf` is the
// direction's solid-angle density at the vertex; 0 marks a delta sample, for
// which `radiance` is already the integral over the delta (an irradiance at
// the vertex). Radiance 0 when the way is blocked.
struct LightSample {
    glm::vec3 direction{0.f};
    float pdf = 0.f;
    float radiance = 0.f;
    Spectrum transmittance{0.f};
    bool is_delta() const { return !(pdf > 0.f); }
};

class LightEstimator {
public:
    virtual ~LightEstimator() = default;
    // A direction from medium vertex p (none: this estimator finds nothing
    // from p). u1, u2 uniform in [0, 1); rng for ratio tracking.
    virtual std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2,
                                              SampleStream& rng, PathCounters& counters) const = 0;
    // For LightHits::WeightedOnExit: the density with which sample(p) makes
    // direction w of a path that scattered at p, left the object at `exit`
    // by one refraction and now travels along w_out inside the light's disc.
    virtual float pdf(const glm::vec3& p, const glm::vec3& w, const glm::vec3& exit,
                      const glm::vec3& w_out, PathCounters& counters) const = 0;
    virtual LightHits hits() const = 0;
};

struct IntegratorSettings;
// The estimator a scene calls for (null: the light is found by hits only).
// The scene must outlive it.
std::unique_ptr<LightEstimator> make_light_estimator(const Scene& scene,
                                                     const IntegratorSettings& settings);

}  // namespace jade
