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
// The one-refraction estimator of the directional light.
std::unique_ptr<LightEstimator> directional_estimator(const Scene& scene,
                                                      const IntegratorSettings& settings) {
    if (scene.interface.mode == BoundaryMode::None)
        return std::make_unique<ShadowRayEstimator>(scene, scene.light, LightHits::Excluded);
    const auto walk = [&] { return std::make_unique<ManifoldEstimator>(scene, scene.light, SpecularChain::Refraction); };
    // Behind a dielectric a delta light is reached only through the walk.
    if (scene.light.is_delta()) return walk();
    switch (settings.light_through_boundary) {
    case LightThroughBoundary::Auto:
        if (scene.light.angular_radius_degrees() < kManifoldBelowDegrees) return walk();
        return std::make_unique<RefractedConeEstimator>(scene);
    case LightThroughBoundary::Manifold: return walk();
    case LightThroughBoundary::Cone: return std::make_unique<RefractedConeEstimator>(scene);
    case LightThroughBoundary::Off: break;
    }
    return nullptr;
}

// A constant environment is met by every path that leaves, whatever its
// direction: phase sampling already finds it as well as sampling it would.
// Only an image, whose radiance varies over the sphere, is sampled. `off`
// turns that off too, for tests and benchmarks; the cone is the disc's.
bool environment_sampled(const Scene& scene, const IntegratorSettings& settings) {
    return scene.environment.is_image() && !scene.environment.black() &&
           settings.light_through_boundary != LightThroughBoundary::Off;
}

std::unique_ptr<LightEstimator> environment_estimator(const Scene& scene) {
    if (scene.interface.mode == BoundaryMode::None)
        return std::make_unique<ShadowRayEstimator>(scene, scene.environment, LightHits::Weighted);
    return std::make_unique<ManifoldEstimator>(scene, scene.environment, SpecularChain::Refraction);
}

// Behind a dielectric, light that reaches a vertex after one internal
// reflection too, by --light-chain. Auto: for a delta light (which nothing
// else reaches along that chain, even with the estimators off, as for its
// one refraction) and for a small disc under auto or manifold; on the demo
// at equal time (README, "How the lights reach the inside") the second
// chain lowered the error 1.35× at 5° and raised it at 20° and under the
// sunrise sky.
bool reflected_chain(const Scene& scene, const IntegratorSettings& settings, const DistantLight& light) {
    if (scene.interface.mode == BoundaryMode::None) return false;
    if (light.is_delta()) return settings.light_chain != LightChain::One;
    const bool off = settings.light_through_boundary == LightThroughBoundary::Off;
    switch (settings.light_chain) {
    case LightChain::One: return false;
    case LightChain::Two: return !off;
    case LightChain::Auto:
        return &light == &scene.light && !off && settings.light_through_boundary != LightThroughBoundary::Cone &&
               scene.light.angular_radius_degrees() < kManifoldBelowDegrees;
    }
    return false;
}
}  // namespace

LightEstimators make_light_estimators(const Scene& scene, const IntegratorSettings& settings) {
    LightEstimators e;
    if (!scene.medium) return e;  // lights are estimated from medium vertices only
    if (scene.light.on()) {
        if (auto one = directional_estimator(scene, settings)) e.directional.push_back(std::move(one));
        if (reflected_chain(scene, settings, scene.light))
            e.directional.push_back(
                std::make_unique<ManifoldEstimator>(scene, scene.light, SpecularChain::ReflectionRefraction));
    }
    if (environment_sampled(scene, settings)) {
        e.environment.push_back(environment_estimator(scene));
        if (reflected_chain(scene, settings, scene.environment))
            e.environment.push_back(
                std::make_unique<ManifoldEstimator>(scene, scene.environment, SpecularChain::ReflectionRefraction));
    }
    return e;
}

}  // namespace jade
