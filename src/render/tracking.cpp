#include "jade/render/tracking.h"

#include <glm/common.hpp>

#include <algorithm>
#include <limits>

namespace jade {

PathCounters& PathCounters::operator+=(const PathCounters& o) {
    paths += o.paths;
    real_collisions += o.real_collisions;
    null_collisions += o.null_collisions;
    surface_events += o.surface_events;
    shadow_rays += o.shadow_rays;
    manifold_walks += o.manifold_walks;
    manifold_failures += o.manifold_failures;
    manifold_probes_ended += o.manifold_probes_ended;
    capped_paths += o.capped_paths;
    sphere_walks += o.sphere_walks;
    return *this;
}

Spectrum ratio_tracking(const Medium& medium, const glm::vec3& o, const glm::vec3& d, float t_max,
                        SampleStream& rng, PathCounters& counters) {
    const Spectrum control = medium.minorant();
    Spectrum tr = majorant_transmittance(control, t_max);
    sample_t_maj(medium, o, d, t_max, kGreyMajorant, control, rng,
                 [&](const glm::vec3&, const MediumProperties& m, const Spectrum& mu, const Spectrum&) {
        ++counters.null_collisions;
        tr *= glm::max(Spectrum(0.f), Spectrum(1.f) - (m.sigma_s + m.sigma_a - control) / mu);
        // Russian roulette on a faint shadow ray keeps it unbiased and short.
        const float q = max_component(tr);
        if (q < 0.1f) {
            if (q <= 0.f || rng.uniform() >= q * 10.f) {
                tr = Spectrum(0.f);
                return false;
            }
            tr /= q * 10.f;
        }
        return true;
    });
    return tr;
}

Spectrum transmittance(const Scene& scene, const glm::vec3& origin, const glm::vec3& direction,
                       SampleStream& rng, PathCounters& counters) {
    constexpr float kInfinity = std::numeric_limits<float>::infinity();
    ++counters.shadow_rays;
    Spectrum tr(1.f);
    glm::vec3 o = origin;
    float query_from = 0.f;  // Scene::spawn_inside
    bool inside = true;      // shadow rays start at medium vertices
    for (int crossing = 0; crossing < kMaxCrossings; ++crossing) {
        const glm::vec3 start = o;
        if (inside && scene.medium &&
            !advance_within_clearance(*scene.boundary, o, direction, [&](float r) {
                tr *= ratio_tracking(*scene.medium, o, direction, r, rng, counters);
                return max_component(tr) > 0.f;
            }))
            return tr;  // ended by roulette before reaching the surface
        const auto hit = scene.boundary->intersect(
            o, direction, std::max(0.f, query_from - glm::length(o - start)), kInfinity);
        if (inside && scene.medium && hit) {  // no hit: out through a crack (Integrator::fly)
            tr *= ratio_tracking(*scene.medium, o, direction, hit->t, rng, counters);
            if (max_component(tr) <= 0.f) return tr;
        }
        if (!hit) return tr;
        const glm::vec3 p = o + hit->t * direction;
        inside = glm::dot(direction, hit->geometric_normal) < 0.f;
        if (glm::dot(direction, hit->geometric_normal) > 0.f && scene.boundary->convex())
            return tr;  // out of a convex object for good
        if (inside) {
            const Scene::Spawn spawn = scene.spawn_inside(p, hit->geometric_normal, direction);
            o = spawn.origin;
            query_from = spawn.query_from;
        } else {
            o = scene.offset(p, hit->geometric_normal, direction);
            query_from = 0.f;
        }
    }
    return Spectrum(0.f);
}

}  // namespace jade
