#pragma once
// Manifold next-event estimation of the directional light through a smooth
// dielectric boundary (Hanika et al. 2015), for one refraction: an exterior
// direction ω is drawn from the light's disc (or is the delta light's one
// direction), and the interior direction w from the vertex that leaves along
// ω is found by Newton's method on the surface (render/specular_manifold.h).
// Its density at the vertex is the disc's density times |dω/dw|, so the
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
    explicit ManifoldEstimator(const Scene& scene) : scene_(scene) {}
    std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                      PathCounters& counters) const override;
    float pdf(const glm::vec3& p, const glm::vec3& w, const glm::vec3& exit, const glm::vec3& w_out,
              PathCounters& counters) const override;
    LightHits hits() const override {
        return scene_.light.is_delta() ? LightHits::Excluded : LightHits::WeightedOnExit;
    }

private:
    const Scene& scene_;
};

}  // namespace jade
