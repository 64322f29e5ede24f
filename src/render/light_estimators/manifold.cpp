#include "jade/render/light_estimators/manifold.h"

#include "jade/core/error.h"
#include "jade/render/specular_manifold.h"

#include <glm/geometric.hpp>

namespace jade {

namespace {
// Two surface points closer than this fraction of the chain's length are
// one solution (the solver stops within kManifoldTolerance of the target).
constexpr float kSameExit = 1e-3f;
}  // namespace

ManifoldEstimator::ManifoldEstimator(const Scene& scene, const DistantLight& light, SpecularChain chain)
    : LightEstimator(light), scene_(scene), chain_(chain) {
    if (chain == SpecularChain::None) throw Error("internal: a manifold estimator needs a specular chain");
}

std::optional<ManifoldEstimator::Found> ManifoldEstimator::solve(const glm::vec3& p, const glm::vec3& target,
                                                                 PathCounters& counters) const {
    if (chain_ == SpecularChain::Refraction) {
        const auto e = solve_refracted_exit(scene_, p, target, counters);
        if (!e) return std::nullopt;
        const glm::vec3 y = p + e->hit.t * e->direction;
        return Found{e->direction, y, y, e->exterior, e->hit.geometric_normal, e->jacobian, e->transmission,
                     e->hit.t, 0.f};
    }
    const auto e = solve_reflected_exit(scene_, p, target, counters);
    if (!e) return std::nullopt;
    return Found{e->direction, e->reflection_point, e->exit_point, e->exterior, e->exit.geometric_normal,
                 e->jacobian,  e->weight,           e->reflection.t, e->exit.t};
}

// Ratio tracking along the chain's legs inside: p → exit, or p → y1 → y2.
Spectrum ManifoldEstimator::Found::transmittance(const Scene& scene, const glm::vec3& p, SampleStream& rng,
                                                 PathCounters& counters) const {
    Spectrum t = ratio_tracking(*scene.medium, p, direction, first_leg, rng, counters);
    if (second_leg > 0.f && max_component(t) > 0.f)
        t *= ratio_tracking(*scene.medium, reflection, glm::normalize(exit - reflection), second_leg, rng, counters);
    return t;
}

std::optional<LightSample> ManifoldEstimator::sample(const glm::vec3& p, float u1, float u2,
                                                     SampleStream& rng,
                                                     PathCounters& counters) const {
    const DistantSample ds = light_.sample(u1, u2);
    if (!light_.is_delta() && !(ds.pdf > 0.f)) return std::nullopt;
    const auto found = solve(p, ds.direction, counters);
    if (!found) return std::nullopt;
    ++counters.shadow_rays;
    LightSample ls;
    ls.direction = found->direction;
    if (scene_.blocked(found->exit, found->exit_normal, found->exterior)) return ls;  // the object itself is in the way
    if (light_.is_delta()) {  // the irradiance, spread by the chain's Jacobian
        ls.radiance = ds.radiance * (found->weight / found->jacobian);
    } else {
        ls.pdf = ds.pdf * found->jacobian;
        ls.radiance = ds.radiance * found->weight;
    }
    ls.transmittance = found->transmittance(scene_, p, rng, counters);
    return ls;
}

float ManifoldEstimator::pdf(const PathToLight& path, PathCounters& counters) const {
    if (path.chain != chain_ || light_.is_delta()) return 0.f;
    const float light_pdf = light_.pdf(path.leaving);
    if (!(light_pdf > 0.f)) return 0.f;
    const auto found = solve(path.vertex, path.leaving, counters);
    if (!found) return 0.f;
    const float same = kSameExit * (found->first_leg + found->second_leg);
    if (glm::length(found->exit - path.exit) > same ||
        (chain_ == SpecularChain::ReflectionRefraction && glm::length(found->reflection - path.reflection) > same))
        return 0.f;  // another solution
    return light_pdf * found->jacobian;
}

}  // namespace jade
