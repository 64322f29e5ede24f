#pragma once
// Straight shadow rays toward the directional light, for an index-matched
// boundary (nothing bends the ray): a direction uniform over the light's
// disc (or the delta light's one direction), its transmittance by ratio
// tracking through every stretch of medium it crosses.

#include "jade/render/light_estimator.h"

namespace jade {

class ShadowRayEstimator final : public LightEstimator {
public:
    explicit ShadowRayEstimator(const Scene& scene) : scene_(scene) {}
    std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                      PathCounters& counters) const override;
    float pdf(const glm::vec3& p, const glm::vec3& w, const glm::vec3& exit, const glm::vec3& w_out,
              PathCounters& counters) const override;
    LightHits hits() const override { return LightHits::Excluded; }

private:
    const Scene& scene_;
};

}  // namespace jade
