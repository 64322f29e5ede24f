#include "jade/render/light_estimators/shadow_ray.h"

namespace jade {

std::optional<UniformCone> ShadowRayEstimator::cone(const glm::vec3&) const {
    return scene_.light.disc();
}

LightArrival ShadowRayEstimator::arriving(const glm::vec3& p, const glm::vec3& w, SampleStream& rng,
                                          PathCounters& counters) const {
    // A delta light delivers its irradiance along its one direction.
    const float radiance =
        scene_.light.is_delta() ? scene_.light.irradiance() : scene_.light.disc_radiance();
    return {radiance, transmittance(scene_, p, w, rng, counters)};
}

}  // namespace jade
