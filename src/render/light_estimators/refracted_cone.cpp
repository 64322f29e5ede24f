#include "jade/render/light_estimators/refracted_cone.h"

#include "jade/render/dielectric.h"

#include <glm/geometric.hpp>

#include <limits>

namespace jade {

namespace {
constexpr float kInfinity = std::numeric_limits<float>::infinity();
}

std::optional<UniformCone> RefractedConeEstimator::cone(const glm::vec3& p) const {
    const BoundaryParams& interface = scene_.interface;
    if (interface.mode == BoundaryMode::Split && !(interface.specular < 1.f))
        return std::nullopt;  // a mirror: nothing leaves
    const glm::vec3& l = scene_.light.direction();
    const auto probe = scene_.boundary->intersect(p, l, 0.f, kInfinity);
    if (!probe || glm::dot(l, probe->geometric_normal) <= 0.f) return std::nullopt;
    // Light arriving along −l refracts into the object (always possible from
    // the outside); the guide is its reverse.
    const BoundaryTransmission in =
        boundary_transmission(interface, -l, interface_normal(*probe, -l, true), true);
    if (in.direction == glm::vec3(0.f)) return std::nullopt;
    const UniformCone cone{-in.direction, scene_.light.disc().cos_max};
    if (cone.is_delta()) return std::nullopt;
    return cone;
}

std::optional<LightSample> RefractedConeEstimator::sample(const glm::vec3& p, float u1, float u2,
                                                         SampleStream& rng,
                                                         PathCounters& counters) const {
    const auto c = cone(p);
    if (!c) return std::nullopt;
    float pdf;
    const glm::vec3 w = c->sample(u1, u2, pdf);
    LightSample ls = light_through_refraction(scene_, p, w, rng, counters);
    ls.direction = w;
    ls.pdf = pdf;
    return ls;
}

float RefractedConeEstimator::pdf(const PathToLight& path, PathCounters&) const {
    if (path.chain != SpecularChain::Refraction) return 0.f;
    const auto c = cone(path.vertex);
    return c ? c->pdf(path.direction) : 0.f;
}

LightSample light_through_refraction(const Scene& scene, const glm::vec3& p, const glm::vec3& w,
                                     SampleStream& rng, PathCounters& counters, PathToLight* path) {
    ++counters.shadow_rays;
    const auto hit = scene.boundary->intersect(p, w, 0.f, kInfinity);
    if (!hit || glm::dot(w, hit->geometric_normal) <= 0.f) return {};
    const BoundaryTransmission out =
        boundary_transmission(scene.interface, w, interface_normal(*hit, w, false), false);
    if (!(out.weight > 0.f) || !on_sampled_side(w, out.direction, hit->geometric_normal, false)) return {};
    const Spectrum le = scene.light.radiance_toward(out.direction);
    if (!(max_component(le) > 0.f)) return {};
    const glm::vec3 y = p + hit->t * w;
    if (scene.blocked(y, hit->geometric_normal, out.direction)) return {};  // the object itself is in the way
    if (path) *path = PathToLight{p, w, out.direction, SpecularChain::Refraction, glm::vec3(0.f), y};
    LightSample ls;
    ls.radiance = out.weight * le;
    ls.transmittance = ratio_tracking(*scene.medium, p, w, hit->t, rng, counters);
    return ls;
}

}  // namespace jade
