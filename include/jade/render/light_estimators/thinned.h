#pragma once
// Another estimator, sampled at a vertex with probability q only (a
// roulette of the light estimate that depends on nothing but q): its
// sample's density is q times the other's, so next-event estimation and
// the paths that meet the light keep one MIS heuristic between them,
// and a delta sample's light is divided by q. Unbiased for any q in (0, 1];
// it pays where an estimate costs many times a path's own step and paths
// find much of the light by themselves (docs/design.md, "Environment
// sampling").

#include "jade/render/light_estimator.h"

#include <memory>

namespace jade {

class ThinnedEstimator final : public LightEstimator {
public:
    ThinnedEstimator(std::unique_ptr<LightEstimator> inner, float probability);
    std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                      PathCounters& counters) const override;
    float pdf(const PathToLight& path, PathCounters& counters) const override;
    LightHits hits() const override { return inner_->hits(); }
    float probability() const { return probability_; }

private:
    std::unique_ptr<LightEstimator> inner_;
    float probability_;
};

}  // namespace jade
