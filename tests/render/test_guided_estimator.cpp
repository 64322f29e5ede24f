// The guided estimator of the light through one refraction
// (render/light_estimators/guided.h), mixed with the cone at half its
// samples, at a fifth, and alone with the cone only where the guide has no
// histogram (a wide disc's default), the guide's own directions half from
// its bins and half from the cell's lobe:
// from vertices inside a sphere its estimate of the light arriving by one
// refraction must equal that integral over all interior directions, drawn
// uniformly and followed the same way; and the density of each sample must
// be the one the estimator gives the path when asked afterwards (MIS with
// the paths that meet the light by themselves depends on it).

#include "jade/geometry/mesh_accel.h"
#include "jade/render/light_estimators/guided.h"
#include "jade/render/light_estimators/refracted_cone.h"
#include "jade/render/light_guide.h"
#include "jade/render/media/homogeneous.h"
#include "jade/render/scene.h"

#include "jade/core/math.h"
#include "jade/core/random.h"
#include "jade/core/sampling.h"

#include "support/render_test_util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

using namespace jade;

namespace {

struct Estimate {
    double mean = 0.0, standard_error = 0.0;
};

// The mean and standard error of n values drawn by `draw`.
template <typename Draw>
Estimate estimate(int n, Draw draw) {
    double sum = 0.0, sum2 = 0.0;
    for (int k = 0; k < n; ++k) {
        const double x = draw(k);
        sum += x;
        sum2 += x * x;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(sum2 / n - mean * mean, 0.0) / (n - 1))};
}

}  // namespace

TEST_CASE("the guided one-refraction estimator integrates the refracted light with and without the cone",
          "[guided][render]") {
    const TriangleMesh sphere = icosphere(4, 1.f);
    const MeshAccel accel(sphere);
    const HomogeneousMedium medium(Spectrum(0.5f), Spectrum(0.2f));
    Scene s = jade_test::basic_scene(accel, &medium, BoundaryMode::Split, Spectrum(0.f));
    s.light = DirectionalLight({0.3f, 0.8f, 0.5f}, 3.f, 20.f);
    const auto guide = std::make_shared<const LightGuide>(s, 1);
    REQUIRE_FALSE(guide->empty());
    PathCounters counters;
    for (const glm::vec3& p : {glm::vec3(0.f), glm::vec3(0.3f, 0.5f, 0.2f), glm::vec3(-0.4f, 0.1f, -0.3f)}) {
        // The truth: interior directions uniform over the sphere, each
        // followed to the light (a homogeneous medium's transmittance is
        // exact: residual ratio tracking has nothing to track).
        const Estimate truth = estimate(1 << 20, [&](int k) {
            SampleStream rng(1, 0, std::uint64_t(k));
            const glm::vec3 w = uniform_cone({0.f, 0.f, 1.f}, -1.f, rng.uniform(), rng.uniform());
            const LightSample ls = light_through_refraction(s, p, w, rng, counters);
            return double(ls.radiance.x * ls.transmittance.x) * 4.0 * kPiD;
        });
        REQUIRE(truth.mean > 0.0);
        // The vertex's cell has a lobe (render/light_guide.h): half the
        // guide's directions come from it, so its density is checked too.
        const int h = guide->histogram(p, SpecularChain::Refraction);
        REQUIRE(h >= 0);
        CHECK(guide->lobe(h, p));
        for (float share : {0.5f, 0.8f, 1.f}) {
            const GuidedEstimator guided(s, SpecularChain::Refraction, guide,
                                         std::make_unique<RefractedConeEstimator>(s), share);
            int lit = 0, mismatched = 0;
            const Estimate e = estimate(1 << 17, [&](int k) {
                SampleStream rng(2, 0, std::uint64_t(k));
                const float u1 = rng.uniform(), u2 = rng.uniform();
                const auto ls = guided.sample(p, u1, u2, rng, counters);
                if (!ls || !(ls->radiance.x > 0.f)) return 0.0;
                ++lit;
                PathToLight path;
                path.vertex = p;
                path.direction = ls->direction;
                path.chain = SpecularChain::Refraction;
                if (std::abs(guided.pdf(path, counters) - ls->pdf) > 1e-4f * ls->pdf) ++mismatched;
                return double(ls->radiance.x * ls->transmittance.x) / double(ls->pdf);
            });
            const double sd = std::sqrt(truth.standard_error * truth.standard_error +
                                        e.standard_error * e.standard_error);
            INFO("vertex (" << p.x << ", " << p.y << ", " << p.z << "), guide share " << share << ": truth "
                            << truth.mean << " ± " << truth.standard_error << ", guided " << e.mean << " ± "
                            << e.standard_error << ", " << lit << " lit samples");
            CHECK(std::abs(e.mean - truth.mean) < 4.0 * sd);
            CHECK(mismatched == 0);
            CHECK(lit > (1 << 17) / 10);
            // Per sample, aimed directions are far sharper than uniform ones.
            CHECK(e.standard_error * e.standard_error * (1 << 17) <
                  0.1 * truth.standard_error * truth.standard_error * (1 << 20));
        }
    }
}
