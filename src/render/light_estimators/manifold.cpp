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
    const UniformCone disc = scene_.light.disc();
    float disc_pdf;
    const glm::vec3 target = disc.sample(u1, u2, disc_pdf);
    const auto exit = solve_refracted_exit(scene_, p, target, counters);
    if (!exit) return std::nullopt;
    ++counters.shadow_rays;
    LightSample ls;
    ls.direction = exit->direction;
    const glm::vec3 y = p + exit->hit.t * exit->direction;
    if (scene_.boundary->intersect(scene_.offset(y, exit->hit.geometric_normal, exit->exterior),
                                   exit->exterior, 0.f, kInfinity))
        return ls;  // the object itself is in the way
    if (disc.is_delta()) {
        ls.radiance = scene_.light.irradiance() * exit->transmission / exit->jacobian;
    } else {
        ls.pdf = disc_pdf * exit->jacobian;
        ls.radiance = scene_.light.disc_radiance() * exit->transmission;
    }
    ls.transmittance = ratio_tracking(*scene_.medium, p, exit->direction, exit->hit.t, rng, counters);
    return ls;
}

float ManifoldEstimator::pdf(const glm::vec3& p, const glm::vec3&, const glm::vec3& exit,
                             const glm::vec3& w_out, PathCounters& counters) const {
    const UniformCone disc = scene_.light.disc();
    if (disc.is_delta()) return 0.f;
    const auto found = solve_refracted_exit(scene_, p, w_out, counters);
    if (!found) return 0.f;
    const glm::vec3 y = p + found->hit.t * found->direction;
    if (glm::length(y - exit) > kSameExit * found->hit.t) return 0.f;  // another solution
    return disc.pdf(w_out) * found->jacobian;
}

}  // namespace jade
