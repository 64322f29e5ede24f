#pragma once
// Light estimators: ways to find the directional light from a medium
// scattering vertex other than waiting for a phase-sampled path to hit it
// (docs/design.md, "Light estimators"). Each one samples a cone of directions
// at the vertex and follows the chosen direction to the light; the
// integrator weighs its estimate against phase sampling by multiple
// importance sampling (the balance heuristic), through the cone's density.
//
// Variants live in render/light_estimators/:
//   shadow_ray      straight shadow rays through an index-matched boundary;
//                   it accounts for all the light (a delta light too)
//   refracted_cone  through a smooth dielectric: a cone aimed so that it
//                   refracts toward the light's disc, MIS-weighted against
//                   paths that leave by one refraction
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
    WeightedOnExit,    // MIS against the cone, for paths that leave the object
                       // by exactly one refraction after the scattering; others fully
};

// What arrives along a sampled direction: the light's radiance (times the
// boundary's transmission weight on the way) and the medium's transmittance.
struct LightArrival {
    float radiance = 0.f;
    Spectrum transmittance{0.f};
};

class LightEstimator {
public:
    virtual ~LightEstimator() = default;
    // The directions sampled at medium vertex p (none: nothing to find here).
    virtual std::optional<UniformCone> cone(const glm::vec3& p) const = 0;
    // The light arriving at p from direction w of cone(p), through what lies
    // between (medium by ratio tracking, the boundary's transmission
    // weight); radiance 0 when blocked. For a delta cone, the irradiance.
    virtual LightArrival arriving(const glm::vec3& p, const glm::vec3& w, SampleStream& rng,
                                  PathCounters& counters) const = 0;
    virtual LightHits hits() const = 0;
};

struct IntegratorSettings;
// The estimator a scene calls for (null: the light is found by hits only).
// The scene must outlive it.
std::unique_ptr<LightEstimator> make_light_estimator(const Scene& scene,
                                                     const IntegratorSettings& settings);

}  // namespace jade
