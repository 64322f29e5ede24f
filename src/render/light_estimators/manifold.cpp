#include "jade/render/light_estimators/manifold.h"

#include "jade/core/error.h"
#include "jade/render/specular_manifold.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

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

std::optional<ManifoldEstimator::Found> ManifoldEstimator::refracted(const glm::vec3& p,
                                                                     const std::optional<RefractedExit>& e) {
    if (!e) return std::nullopt;
    const glm::vec3 y = p + e->hit.t * e->direction;
    return Found{e->direction, y, y, e->exterior, e->hit.geometric_normal, e->jacobian, e->transmission,
                 e->hit.t, 0.f};
}

std::optional<ManifoldEstimator::Found> ManifoldEstimator::solve(const glm::vec3& p, const glm::vec3& target,
                                                                 PathCounters& counters) const {
    if (chain_ == SpecularChain::Refraction) return refracted(p, solve_refracted_exit(scene_, p, target, counters));
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

float probe_survival(const Scene& scene, float probe_distance) {
    if (!scene.medium) return 1.f;
    const float transmittance = std::exp(-min_component(scene.medium->minorant()) * probe_distance);
    return std::clamp(transmittance / kProbeFullTransmittance, kProbeMinSurvival, 1.f);
}

std::optional<LightSample> ManifoldEstimator::sample(const glm::vec3& p, float u1, float u2,
                                                     SampleStream& rng,
                                                     PathCounters& counters) const {
    const DistantSample ds = light_.sample(u1, u2);
    if (!light_.is_delta() && !(ds.pdf > 0.f)) return std::nullopt;
    // A delta light has no MIS partner, so its one-refraction walk may be
    // ended by roulette after its probe (probe_survival); a disc's density
    // would have to carry the survival into pdf() as well.
    float survival = 1.f;
    std::optional<Found> found;
    if (light_.is_delta() && chain_ == SpecularChain::Refraction) {
        const auto seed = refraction_seed(scene_, p, ds.direction);
        if (seed) survival = probe_survival(scene_, seed->probe_distance);
        if (survival < 1.f && !(rng.uniform() < survival)) {
            ++counters.manifold_probes_ended;
            return std::nullopt;
        }
        found = refracted(p, solve_refracted_exit(scene_, p, ds.direction, seed, counters));
    } else {
        found = solve(p, ds.direction, counters);
    }
    if (!found) return std::nullopt;
    ++counters.shadow_rays;
    LightSample ls;
    ls.direction = found->direction;
    if (scene_.blocked(found->exit, found->exit_normal, found->exterior)) return ls;  // the object itself is in the way
    if (light_.is_delta()) {  // the irradiance, spread by the chain's Jacobian
        ls.radiance = ds.radiance * (found->weight / (found->jacobian * survival));
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
