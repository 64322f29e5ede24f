#pragma once
// Manifold next-event estimation of a light at infinity through a smooth
// dielectric boundary (Hanika et al. 2015), along one specular chain: one
// refraction out, or one internal reflection and then the refraction out.
// An exterior direction ω is drawn from the light (a point of the
// directional light's disc, the delta light's one direction, or the
// environment image's importance sampling), and the interior direction w
// from the vertex whose chain leaves along ω is found by Newton's method on
// the surface (render/specular_manifold.h). Its density at the vertex is
// the light's density of ω times |dω/dw|, so the sample is weighed against
// phase sampling by MIS (a phase-sampled path that leaves by the same chain
// counts the light with the density the solver would have given its
// direction, 0 when the solver does not find that chain). A delta light has
// only these estimators: the estimate is E · weight / |dω/dw| (over the
// walk's survival past its probe, probe_survival below), unbiased
// wherever the chain from a vertex is unique (for one refraction, convex
// parts of the surface; a concave surface seen from inside can refract two
// paths toward one direction, and the solver finds one of them: the walks
// that fail are counted).

#include "jade/render/light_estimator.h"
#include "jade/render/specular_manifold.h"

namespace jade {

// A delta light's one-refraction walk past its probe (render/
// specular_manifold.h, refraction_seed): the probe already tells how far the
// surface lies toward the light, and past a few mean free paths the light
// that arrives is small while the walk costs as much. So the walk goes on
// with probability min(1, T / kProbeFullTransmittance), at least
// kProbeMinSurvival, where T = e^(−σ_min · probe distance) in the channel the
// medium's extinction lets through most (its minorant); the light of a walk
// that goes on is weighed by the inverse (a roulette: unbiased). 1 without a
// medium. docs/design.md, "What a delta light's walks cost".
constexpr float kProbeFullTransmittance = 0.25f;
constexpr float kProbeMinSurvival = 0.05f;
float probe_survival(const Scene& scene, float probe_distance);

class ManifoldEstimator final : public LightEstimator {
public:
    // chain: Refraction or ReflectionRefraction.
    ManifoldEstimator(const Scene& scene, const DistantLight& light, SpecularChain chain);
    std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                      PathCounters& counters) const override;
    float pdf(const PathToLight& path, PathCounters& counters) const override;
    LightHits hits() const override { return LightHits::Weighted; }

private:
    // The chain from p that leaves along `target`, as the solver finds it.
    // (For one refraction, reflection = exit and the second leg is empty.)
    struct Found {
        glm::vec3 direction, reflection, exit, exterior, exit_normal;
        float jacobian, weight, first_leg, second_leg;
        Spectrum transmittance(const Scene& scene, const glm::vec3& p, SampleStream& rng,
                               PathCounters& counters) const;
    };
    std::optional<Found> solve(const glm::vec3& p, const glm::vec3& target, PathCounters& counters) const;
    static std::optional<Found> refracted(const glm::vec3& p, const std::optional<RefractedExit>& exit);

    const Scene& scene_;
    SpecularChain chain_;
};

}  // namespace jade
