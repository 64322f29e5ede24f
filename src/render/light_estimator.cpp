#include "jade/render/light_estimator.h"

#include "jade/render/integrator.h"
#include "jade/render/light_estimators/guided.h"
#include "jade/render/light_estimators/manifold.h"
#include "jade/render/light_estimators/refracted_cone.h"
#include "jade/render/light_estimators/shadow_ray.h"
#include "jade/render/light_estimators/thinned.h"

namespace jade {

namespace {
// Below this angular radius `auto` takes the manifold walk, above it the
// cone. On the demo at equal time (256², 30 s; README, "Benchmarks") the
// walk costs 1.6× the cone per sample; its variance per sample is 2.9×
// lower at 5° and equal at 20°, where the cone already covers the disc's
// preimage well. The crossover lies between; 10° is taken.
constexpr float kManifoldBelowDegrees = 10.f;
// The same with the light guide mixed in (render/light_guide.h), which
// covers what the cone misses: on the demo at equal time the cone was
// better at 5° (relative MSE 0.0056 against 0.0065) and the walk at 2.5°
// (0.0077 against 0.0083).
constexpr float kGuidedManifoldBelowDegrees = 4.f;
// From this angular radius on, `auto` draws every one-refraction direction
// from the guide where the vertex's cell has a histogram (kWideDiscGuideShare,
// against half below it), and the cone only where it has none: the disc's
// preimage inside (its radius over the index of refraction, about 9° here)
// then spans more than one of the guide's 8.5° bins, and the cell's lobe
// (render/light_guide.h) covers it at the vertex itself, so the cone's
// samples, each needing a probe ray, add less than they cost. The cone
// kept 0.2 of them while the guide had its bins alone: its density was a
// floor inside the cone for the paths that meet the light by themselves
// (with the bins alone the second moment of their light grew fourfold). On
// the demo at equal time (256², 30 s, seed pairs 1–2, 3–4, 5–6, one
// sitting) the relative MSE at 20° was 0.00115 with the bins and the cone
// at 0.2 and 0.00111 with the bins alone; in another, 0.00133 with the
// bins and the cone at 0.2 and 0.00112 with the lobes and no cone
// (docs/design.md, "The cells' lobes").
constexpr float kWideDiscFromDegrees = 15.f;
constexpr float kWideDiscGuideShare = 1.f;
// A delta light's light after one internal reflection is estimated at this
// share of the vertices only (ThinnedEstimator): the two-vertex walk costs
// about four times everything else a sample does, and that light is 0.1–0.3 %
// of the demo's image. On the demo's volume in the vase under a delta light
// (256², 128 spp, seeds 1 and 2) every vertex took 78–80 s, a share of 0.02
// took 19 s, against 17 s without that chain, at the same estimated error
// (0.0766 against 0.0769–0.0777: that light's noise is lost in the rest).
constexpr float kDeltaReflectedShare = 0.02f;
}  // namespace

namespace {
// The one-refraction estimator of the directional light (before the
// guide, if any, is mixed in).
std::unique_ptr<LightEstimator> directional_estimator(const Scene& scene, const IntegratorSettings& settings,
                                                      bool guided) {
    if (scene.interface.mode == BoundaryMode::None)
        return std::make_unique<ShadowRayEstimator>(scene, scene.light, LightHits::Excluded);
    const auto walk = [&] { return std::make_unique<ManifoldEstimator>(scene, scene.light, SpecularChain::Refraction); };
    // Behind a dielectric a delta light is reached only through the walk.
    if (scene.light.is_delta()) return walk();
    switch (settings.light_through_boundary) {
    case LightThroughBoundary::Auto:
        if (scene.light.angular_radius_degrees() < (guided ? kGuidedManifoldBelowDegrees : kManifoldBelowDegrees))
            return walk();
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

// Through a dielectric, the environment's walks along a chain, estimated
// at a share of the vertices only (IntegratorSettings::environment_share;
// ThinnedEstimator).
std::unique_ptr<LightEstimator> environment_walk(const Scene& scene, const IntegratorSettings& settings,
                                                 SpecularChain chain) {
    auto walk = std::make_unique<ManifoldEstimator>(scene, scene.environment, chain);
    if (settings.environment_share >= 1.f) return walk;
    return std::make_unique<ThinnedEstimator>(std::move(walk), settings.environment_share);
}

std::unique_ptr<LightEstimator> environment_estimator(const Scene& scene, const IntegratorSettings& settings) {
    if (scene.interface.mode == BoundaryMode::None)
        return std::make_unique<ShadowRayEstimator>(scene, scene.environment, LightHits::Weighted);
    return environment_walk(scene, settings, SpecularChain::Refraction);
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

// The directional light's guide (render/light_guide.h), when its
// estimators use one: a disc behind a dielectric, estimated (not `off`).
std::shared_ptr<const LightGuide> light_guide_for(const Scene& scene, const IntegratorSettings& settings,
                                                  std::uint64_t seed) {
    if (!settings.light_guide || scene.light.is_delta() || scene.interface.mode == BoundaryMode::None ||
        settings.light_through_boundary == LightThroughBoundary::Off)
        return nullptr;
    std::shared_ptr<const LightGuide> guide = settings.built_light_guide;
    if (!guide) {
        LightGuideSettings guide_settings;
        guide_settings.photons = settings.light_guide_photons;
        guide = std::make_shared<const LightGuide>(scene, seed, guide_settings);
    }
    if (guide->empty()) return nullptr;
    return guide;
}

// Written with the densities' ratio, so that no square overflows.
float mis_weight(MisHeuristic heuristic, float pdf_this, float pdf_other) {
    const float r = pdf_other / pdf_this;
    return heuristic == MisHeuristic::Power ? 1.f / (1.f + r * r) : 1.f / (1.f + r);
}

LightEstimators make_light_estimators(const Scene& scene, const IntegratorSettings& settings,
                                      std::uint64_t seed) {
    LightEstimators e;
    if (!scene.medium) return e;  // lights are estimated from medium vertices only
    if (scene.light.on()) {
        const std::shared_ptr<const LightGuide> guide = light_guide_for(scene, settings, seed);
        std::unique_ptr<LightEstimator> one = directional_estimator(scene, settings, guide != nullptr), two, outside;
        // With a guide, auto leaves the second chain to it: on the demo the
        // guide alone beat it mixed with the walk at 5° (README, "How the
        // lights reach the inside").
        if (reflected_chain(scene, settings, scene.light) && !(guide && settings.light_chain == LightChain::Auto)) {
            two = std::make_unique<ManifoldEstimator>(scene, scene.light, SpecularChain::ReflectionRefraction);
            if (scene.light.is_delta())
                two = std::make_unique<ThinnedEstimator>(std::move(two), kDeltaReflectedShare);
        }
        if (guide) {
            const bool wide = settings.light_through_boundary == LightThroughBoundary::Auto &&
                              scene.light.angular_radius_degrees() >= kWideDiscFromDegrees;
            one = std::make_unique<GuidedEstimator>(scene, SpecularChain::Refraction, guide, std::move(one),
                                                    wide ? kWideDiscGuideShare : GuidedEstimator::kHalfShare);
            if (settings.light_chain != LightChain::One)
                two = std::make_unique<GuidedEstimator>(scene, SpecularChain::ReflectionRefraction, guide,
                                                        std::move(two));
            outside = std::make_unique<GuidedEstimator>(scene, SpecularChain::RefractionReflection, guide, nullptr);
        }
        for (auto* estimator : {&one, &two, &outside})
            if (*estimator) e.directional.push_back(std::move(*estimator));
    }
    if (environment_sampled(scene, settings)) {
        e.environment.push_back(environment_estimator(scene, settings));
        if (reflected_chain(scene, settings, scene.environment))
            e.environment.push_back(environment_walk(scene, settings, SpecularChain::ReflectionRefraction));
    }
    return e;
}

}  // namespace jade
