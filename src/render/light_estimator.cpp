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

namespace {
std::unique_ptr<LightEstimator> directional_estimator(const Scene& scene,
                                                      const IntegratorSettings& settings) {
    if (!scene.light.on()) return nullptr;
    if (scene.interface.mode == BoundaryMode::None)
        return std::make_unique<ShadowRayEstimator>(scene, scene.light, LightHits::Excluded);
    // Behind a dielectric a delta light is reached only through the walk.
    if (scene.light.is_delta()) return std::make_unique<ManifoldEstimator>(scene, scene.light);
    switch (settings.light_through_boundary) {
    case LightThroughBoundary::Auto:
        if (scene.light.angular_radius_degrees() < kManifoldBelowDegrees)
            return std::make_unique<ManifoldEstimator>(scene, scene.light);
        return std::make_unique<RefractedConeEstimator>(scene);
    case LightThroughBoundary::Manifold: return std::make_unique<ManifoldEstimator>(scene, scene.light);
    case LightThroughBoundary::Cone: return std::make_unique<RefractedConeEstimator>(scene);
    case LightThroughBoundary::Off: break;
    }
    return nullptr;
}

// A constant environment is met by every path that leaves, whatever its
// direction: phase sampling already finds it as well as sampling it would.
// Only an image, whose radiance varies over the sphere, is sampled. `off`
// turns that off too, for tests and benchmarks; the cone is the disc's.
std::unique_ptr<LightEstimator> environment_estimator(const Scene& scene,
                                                      const IntegratorSettings& settings) {
    if (!scene.environment.is_image() || scene.environment.black()) return nullptr;
    if (settings.light_through_boundary == LightThroughBoundary::Off) return nullptr;
    if (scene.interface.mode == BoundaryMode::None)
        return std::make_unique<ShadowRayEstimator>(scene, scene.environment, LightHits::Weighted);
    return std::make_unique<ManifoldEstimator>(scene, scene.environment);
}
}  // namespace

LightEstimators make_light_estimators(const Scene& scene, const IntegratorSettings& settings) {
    LightEstimators e;
    if (!scene.medium) return e;  // lights are estimated from medium vertices only
    e.directional = directional_estimator(scene, settings);
    e.environment = environment_estimator(scene, settings);
    return e;
}

}  // namespace jade
