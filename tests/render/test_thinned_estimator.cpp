// A thinned light estimator against its definition: sampled at a vertex
// with probability q, its density q times the other's, a delta sample's
// light divided by q, so that the estimate's mean is the other's.

#include "jade/render/light_estimators/thinned.h"
#include "jade/core/error.h"
#include "jade/core/random.h"
#include "jade/render/light.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jade;

namespace {

// Always the same sample: a direction of density `pdf` (0: a delta) and
// radiance 2.
class FixedEstimator final : public LightEstimator {
public:
    FixedEstimator(const DistantLight& light, float pdf) : LightEstimator(light), pdf_(pdf) {}
    std::optional<LightSample> sample(const glm::vec3&, float, float, SampleStream&, PathCounters&) const override {
        return LightSample{glm::vec3(0.f, 0.f, 1.f), pdf_, Spectrum(2.f), Spectrum(1.f)};
    }
    float pdf(const PathToLight&, PathCounters&) const override { return pdf_; }
    LightHits hits() const override { return LightHits::Weighted; }

private:
    float pdf_;
};

// The mean over n vertices of what the estimate adds without MIS:
// radiance / pdf, or the delta's radiance.
double mean_estimate(const LightEstimator& e, int n, std::uint64_t seed) {
    SampleStream rng(seed, 0, 0);
    PathCounters counters;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const auto s = e.sample(glm::vec3(0.f), 0.5f, 0.5f, rng, counters);
        if (s) sum += s->is_delta() ? double(s->radiance.x) : double(s->radiance.x) / double(s->pdf);
    }
    return sum / n;
}

}  // namespace

TEST_CASE("a thinned estimator samples a share q of the vertices at q times the density", "[light]") {
    const Environment sky(Spectrum(1.f));
    const float q = 0.1f;
    const ThinnedEstimator thinned(std::make_unique<FixedEstimator>(sky, 0.5f), q);
    PathCounters counters;
    CHECK(thinned.pdf(PathToLight{}, counters) == Approx(0.05f));
    CHECK(thinned.hits() == LightHits::Weighted);
    // The estimate's mean is the other's, 2 / 0.5 = 4: a share q of the
    // vertices give 4 / q, a binomial count with standard error
    // 4 √((1 − q)/(q n)) = 0.027 at n = 200 000; five of them.
    const int n = 200000;
    CHECK(std::abs(mean_estimate(thinned, n, 3) - 4.0) < 5.0 * 4.0 * std::sqrt((1.0 - q) / (q * n)));
    // A delta sample's light is divided by q instead.
    const ThinnedEstimator delta(std::make_unique<FixedEstimator>(sky, 0.f), q);
    CHECK(std::abs(mean_estimate(delta, n, 4) - 2.0) < 5.0 * 2.0 * std::sqrt((1.0 - q) / (q * n)));
    // At q = 1 it is the other estimator.
    const ThinnedEstimator all(std::make_unique<FixedEstimator>(sky, 0.5f), 1.f);
    CHECK(mean_estimate(all, 1000, 5) == Approx(4.0));
    CHECK_THROWS_AS(ThinnedEstimator(std::make_unique<FixedEstimator>(sky, 0.5f), 0.f), Error);
    CHECK_THROWS_AS(ThinnedEstimator(std::make_unique<FixedEstimator>(sky, 0.5f), 1.5f), Error);
}
