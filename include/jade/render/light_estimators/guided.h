#pragma once
// Next-event estimation of the directional light through a smooth
// dielectric along one specular chain (one refraction out, an internal
// reflection and then the refraction, or the refraction and a reflection
// off the outside of another part of the object), with directions drawn from the
// light guide of the vertex's cell (render/light_guide.h; docs/design.md,
// "Light guide") and followed exactly: traced to the surface, reflected
// and refracted there with the interface's weights, ratio-tracked, counted
// if they leave inside the disc.
//
// Where another estimator covers the same chain (the cone or the manifold
// walk), a share of the samples are its own (half by default), and all of
// them where the guide has no histogram. It aims at one surface point:
// where the light's axis leaves, or where the walk's seed lies. The guide
// has traced the light in through every face, so a vertex whose light
// comes in by another face (under a vase's rim, lit through its top) is
// reached as well. A wide disc's preimage spans several of the guide's
// bins and the cell's lobe covers it at the vertex, and the guide then
// takes all the samples where it has a histogram (docs/design.md, "Light
// guide"). To the integrator it is one estimator: its density, the
// mixture's, is known for every path of the chain, so the paths that meet
// the light by themselves are weighed against it by MIS as before.

#include "jade/render/light_estimator.h"
#include "jade/render/light_guide.h"

#include <memory>

namespace jade {

class GuidedEstimator final : public LightEstimator {
public:
    // The guide's share of the samples where another estimator covers the
    // chain too, unless told otherwise. Half: where the other aims well,
    // its half keeps most of its strength, and where it misses, the
    // guide's half finds the light.
    static constexpr float kHalfShare = 0.5f;

    // The estimator of scene.light along `chain` (not None) from `guide`,
    // that light's guide, mixed with `other` (null: none), an estimator of
    // the same light and chain, which draws 1 − guide_share of the samples
    // (guide_share in (0, 1]) and all of them where the guide has none.
    GuidedEstimator(const Scene& scene, SpecularChain chain, std::shared_ptr<const LightGuide> guide,
                    std::unique_ptr<LightEstimator> other, float guide_share = kHalfShare);
    std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                      PathCounters& counters) const override;
    float pdf(const PathToLight& path, PathCounters& counters) const override;
    LightHits hits() const override { return LightHits::Weighted; }

private:
    // The light arriving at p along interior direction w by the chain.
    LightSample follow(const glm::vec3& p, const glm::vec3& w, SampleStream& rng, PathCounters& counters,
                       PathToLight& path) const;
    LightSample through_reflection(const glm::vec3& p, const glm::vec3& w, SampleStream& rng,
                                   PathCounters& counters, PathToLight& path) const;
    LightSample reflected_outside(const glm::vec3& p, const glm::vec3& w, SampleStream& rng,
                                  PathCounters& counters, PathToLight& path) const;
    struct Mixture {
        float sampled;  // the probability that a vertex gets a sample
        float guided;   // the share of those drawn from the guide
    };
    Mixture mixture(int h) const;
    float other_pdf(const Mixture& m, const PathToLight& path, PathCounters& counters) const;
    float density(const LightGuide::Site& site, const Mixture& m, const glm::vec3& w, float other) const;

    const Scene& scene_;
    SpecularChain chain_;
    std::shared_ptr<const LightGuide> guide_;
    std::unique_ptr<LightEstimator> other_;
    float guide_share_;
};

}  // namespace jade
