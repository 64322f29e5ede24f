#include "jade/render/light_estimators/shadow_ray.h"

namespace jade {

std::optional<LightSample> ShadowRayEstimator::sample(const glm::vec3& p, float u1, float u2,
                                                      SampleStream& rng,
                                                      PathCounters& counters) const {
    const DistantSample ds = light_.sample(u1, u2);
    if (!light_.is_delta() && !(ds.pdf > 0.f)) return std::nullopt;
    LightSample ls;
    ls.direction = ds.direction;
    ls.pdf = ds.pdf;  // 0 for a delta light, whose radiance is its irradiance
    ls.radiance = ds.radiance;
    ls.transmittance = transmittance(scene_, p, ls.direction, rng, counters);
    return ls;
}

float ShadowRayEstimator::pdf(const PathToLight& path, PathCounters&) const {
    return path.chain == SpecularChain::None ? light_.pdf(path.leaving) : 0.f;
}

}  // namespace jade
