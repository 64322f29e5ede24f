#pragma once
// Manifold next-event estimation of a light at infinity through a smooth
// dielectric boundary (Hanika et al. 2015), for one refraction: an exterior
// direction ω is drawn from the light (a point of the directional light's
// disc, the delta light's one direction, or the environment image's
// importance sampling), and the interior direction w from the vertex that leaves along
// ω is found by Newton's method on the surface (render/specular_manifold.h).
// Its density at the vertex is the light's density of ω times |dω/dw|, so the
// sample is weighed against phase sampling by MIS exactly like the cone's
// (a phase-sampled path that leaves by one refraction counts the light with
// the density the solver would have given its direction, 0 when the solver
// does not find that exit). A delta light has only this estimator: its
// estimate is E · T / |dω/dw|, unbiased wherever the refraction path from a
// vertex is unique (convex parts of the surface; a concave surface seen
// from inside can refract two paths toward one direction, and the solver
// finds one of them: the walks that fail are counted).

#include "jade/render/light_estimator.h"

namespace jade {

class ManifoldEstimator final : public LightEstimator {
public:
    ManifoldEstimator(const Scene& scene, const DistantLight& light)
        : LightEstimator(light), scene_(scene) {}
    std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                      PathCounters& counters) const override;
    float pdf(const PathToLight& path, PathCounters& counters) const override;
    LightHits hits() const override { return LightHits::Weighted; }

private:
    const Scene& scene_;
};

}  // namespace jade
