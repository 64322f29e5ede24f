#include "jade/render/light_estimators/shadow_ray.h"

namespace jade {

std::optional<LightSample> ShadowRayEstimator::sample(const glm::vec3& p, float u1, float u2,
                                                      SampleStream& rng,
                                                      PathCounters& counters) const {
    const UniformCone disc = scene_.light.disc();
    LightSample ls;
    ls.direction = disc.sample(u1, u2, ls.pdf);
    // A delta light delivers its irradiance along its one direction.
    if (disc.is_delta()) {
        ls.pdf = 0.f;
        ls.radiance = scene_.light.irradiance();
    } else {
        ls.radiance = scene_.light.disc_radiance();
    }
    ls.transmittance = transmittance(scene_, p, ls.direction, rng, counters);
    return ls;
}

float ShadowRayEstimator::pdf(const glm::vec3&, const glm::vec3& w, const glm::vec3&,
                              const glm::vec3&, PathCounters&) const {
    return scene_.light.disc().pdf(w);
}

}  // namespace jade
