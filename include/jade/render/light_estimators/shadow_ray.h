#pragma once
// Straight shadow rays toward a light at infinity, for an index-matched
// boundary (nothing bends the ray): a direction drawn from the light (uniform
// over the directional light's disc, the delta light's one direction, or the
// environment image's importance sampling), its transmittance by ratio
// tracking through every stretch of medium it crosses. Its paths are exactly
// the straight ones; `hits` says whether paths that meet the light straight
// from a vertex count none of it (the directional light: its disc is small
// and seen alike from every vertex) or are weighed by MIS (the environment:
// a forward-scattering phase function can find a wide sky better).

#include "jade/render/light_estimator.h"

namespace jade {

class ShadowRayEstimator final : public LightEstimator {
public:
    ShadowRayEstimator(const Scene& scene, const DistantLight& light, LightHits hits)
        : LightEstimator(light), scene_(scene), hits_(hits) {}
    std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                      PathCounters& counters) const override;
    float pdf(const PathToLight& path, PathCounters& counters) const override;
    LightHits hits() const override { return hits_; }

private:
    const Scene& scene_;
    LightHits hits_;
};

}  // namespace jade
