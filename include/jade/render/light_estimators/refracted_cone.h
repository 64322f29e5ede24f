#pragma once
// Next-event estimation of the directional light through a smooth dielectric
// boundary. No straight shadow ray reaches a light behind a refracting
// surface, but a direction from a medium vertex can be chosen that will
// refract toward it: the guide is the interior direction that leaves along
// the light's axis through the surface point the axis itself meets (found by
// one probe ray), and directions are drawn uniformly from a cone of the
// light's angular radius around it. The sampled ray is then followed
// exactly: ratio-tracked to the boundary, refracted there with the
// interface's transmission weight, and counted if it leaves the scene inside
// the light's disc. The guide depends only on the vertex, so the cone's
// density is known for any direction, and the estimate is combined with phase
// sampling (a path that scatters, refracts out once and escapes) by multiple
// importance sampling. It is a one-refraction special case of manifold
// next-event estimation (Hanika et al. 2015), kept unbiased by the exact
// tracing instead of a Newton solve. A delta light cannot be reached this way.

#include "jade/render/light_estimator.h"

namespace jade {

class RefractedConeEstimator final : public LightEstimator {
public:
    // For the scene's directional light (a disc, not a delta light).
    explicit RefractedConeEstimator(const Scene& scene) : LightEstimator(scene.light), scene_(scene) {}
    std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                      PathCounters& counters) const override;
    float pdf(const PathToLight& path, PathCounters& counters) const override;
    LightHits hits() const override { return LightHits::Weighted; }

private:
    // The directions sampled at p (none when the guide cannot be found).
    std::optional<UniformCone> cone(const glm::vec3& p) const;

    const Scene& scene_;
};

// The directional light arriving at medium vertex p along interior
// direction w by one refraction out: its radiance times the boundary's
// weight (0 when blocked or outside the disc) and the medium's
// transmittance, ratio-tracked (direction and pdf are the caller's).
// `path`, when given, receives the path this makes (chain Refraction).
LightSample light_through_refraction(const Scene& scene, const glm::vec3& p, const glm::vec3& w,
                                     SampleStream& rng, PathCounters& counters,
                                     PathToLight* path = nullptr);

}  // namespace jade
