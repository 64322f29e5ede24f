#include "jade/render/light_estimators/thinned.h"

#include "jade/core/error.h"
#include "jade/core/random.h"

namespace jade {

ThinnedEstimator::ThinnedEstimator(std::unique_ptr<LightEstimator> inner, float probability)
    : LightEstimator(inner->light()), inner_(std::move(inner)), probability_(probability) {
    if (!(probability > 0.f && probability <= 1.f))
        throw Error("internal: a thinned estimator's probability lies in (0, 1]");
}

std::optional<LightSample> ThinnedEstimator::sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                                    PathCounters& counters) const {
    if (probability_ < 1.f && !(rng.uniform() < probability_)) return std::nullopt;
    std::optional<LightSample> s = inner_->sample(p, u1, u2, rng, counters);
    if (!s) return s;
    if (s->is_delta())
        s->radiance /= probability_;
    else
        s->pdf *= probability_;
    return s;
}

float ThinnedEstimator::pdf(const PathToLight& path, PathCounters& counters) const {
    return probability_ * inner_->pdf(path, counters);
}

}  // namespace jade
