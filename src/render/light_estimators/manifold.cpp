#include "jade/render/light_estimators/manifold.h"

#include "jade/render/specular_manifold.h"

#include <glm/geometric.hpp>

#include <limits>

namespace jade {

namespace {
constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Two exits closer than this fraction of their distance from the vertex are
// one solution (the solver stops within kManifoldTolerance of the target).
constexpr float kSameExit = 1e-3f;
}  // namespace

std::optional<LightSample> ManifoldEstimator::sample(const glm::vec3& p, float u1, float u2,
                                                     SampleStream& rng,
                                                     PathCounters& counters) const {
    const DistantSample ds = light_.sample(u1, u2);
    if (!light_.is_delta() && !(ds.pdf > 0.f)) return std::nullopt;
    const auto exit = solve_refracted_exit(scene_, p, ds.direction, counters);
    if (!exit) return std::nullopt;
    ++counters.shadow_rays;
    LightSample ls;
    ls.direction = exit->direction;
    const glm::vec3 y = p + exit->hit.t * exit->direction;
    const bool outward = glm::dot(exit->exterior, exit->hit.geometric_normal) > 0.f;
    if (!(outward && scene_.boundary->convex()) &&
        scene_.boundary->intersect(scene_.offset(y, exit->hit.geometric_normal, exit->exterior),
                                   exit->exterior, 0.f, kInfinity))
        return ls;  // the object itself is in the way
    if (light_.is_delta()) {  // the irradiance, spread by the refraction's Jacobian
        ls.radiance = ds.radiance * (exit->transmission / exit->jacobian);
    } else {
        ls.pdf = ds.pdf * exit->jacobian;
        ls.radiance = ds.radiance * exit->transmission;
    }
    ls.transmittance = ratio_tracking(*scene_.medium, p, exit->direction, exit->hit.t, rng, counters);
    return ls;
}

float ManifoldEstimator::pdf(const PathToLight& path, PathCounters& counters) const {
    if (!path.exit || light_.is_delta()) return 0.f;
    const float light_pdf = light_.pdf(path.leaving);
    if (!(light_pdf > 0.f)) return 0.f;
    const auto found = solve_refracted_exit(scene_, path.vertex, path.leaving, counters);
    if (!found) return 0.f;
    const glm::vec3 y = path.vertex + found->hit.t * found->direction;
    if (glm::length(y - *path.exit) > kSameExit * found->hit.t) return 0.f;  // another solution
    return light_pdf * found->jacobian;
}

}  // namespace jade
