#include "jade/render/light_estimator.h"

#include "jade/render/integrator.h"
#include "jade/render/light_estimators/manifold.h"
#include "jade/render/light_estimators/refracted_cone.h"
#include "jade/render/light_estimators/shadow_ray.h"

namespace jade {

namespace {
// Below this angular radius `auto` takes the manifold walk, above it the
// cone. On the demo at equal time (256², 30 s; README, "Benchmarks") the
// walk costs 1.6× the cone per sample; its variance per sample is 2.9×
// lower at 5° and equal at 20°, where the cone already covers the disc's
// preimage well. The crossover lies between; 10° is taken.
constexpr float kManifoldBelowDegrees = 10.f;
}  // namespace

std::unique_ptr<LightEstimator> make_light_estimator(const Scene& scene,
                                                     const IntegratorSettings& settings) {
    if (!scene.light.on()) return nullptr;
    if (scene.interface.mode == BoundaryMode::None)
        return std::make_unique<ShadowRayEstimator>(scene);
    // Behind a dielectric the light is reached only from a medium, and a
    // delta light only through the manifold walk.
    if (!scene.medium) return nullptr;
    if (scene.light.is_delta()) return std::make_unique<ManifoldEstimator>(scene);
    switch (settings.light_through_boundary) {
    case LightThroughBoundary::Auto:
        if (scene.light.angular_radius_degrees() < kManifoldBelowDegrees)
            return std::make_unique<ManifoldEstimator>(scene);
        return std::make_unique<RefractedConeEstimator>(scene);
    case LightThroughBoundary::Manifold: return std::make_unique<ManifoldEstimator>(scene);
    case LightThroughBoundary::Cone: return std::make_unique<RefractedConeEstimator>(scene);
    case LightThroughBoundary::Off: break;
    }
    return nullptr;
}

}  // namespace jade
