#include "jade/render/light_estimator.h"

#include "jade/render/integrator.h"
#include "jade/render/light_estimators/refracted_cone.h"
#include "jade/render/light_estimators/shadow_ray.h"

namespace jade {

std::unique_ptr<LightEstimator> make_light_estimator(const Scene& scene,
                                                     const IntegratorSettings& settings) {
    if (!scene.light.on()) return nullptr;
    if (scene.interface.mode == BoundaryMode::None)
        return std::make_unique<ShadowRayEstimator>(scene);
    // Behind a dielectric only a disc can be reached, and only from a medium.
    if (scene.medium && settings.light_through_boundary && !scene.light.is_delta())
        return std::make_unique<RefractedConeEstimator>(scene);
    return nullptr;
}

}  // namespace jade
