#include "jade/render/light_estimators/guided.h"

#include "jade/core/error.h"
#include "jade/render/dielectric.h"
#include "jade/render/light_estimators/refracted_cone.h"
#include "jade/render/specular_manifold.h"

#include <glm/geometric.hpp>

#include <limits>

namespace jade {

namespace {
constexpr float kInfinity = std::numeric_limits<float>::infinity();
}  // namespace

GuidedEstimator::GuidedEstimator(const Scene& scene, SpecularChain chain, std::shared_ptr<const LightGuide> guide,
                                 std::unique_ptr<LightEstimator> other, float guide_share)
    : LightEstimator(scene.light), scene_(scene), chain_(chain),
      guide_(std::move(guide)),
      other_(std::move(other)), guide_share_(guide_share) {
    if (chain == SpecularChain::None || !guide_) throw Error("internal: a guided estimator needs a chain and a guide");
    if (!(guide_share_ > 0.f && guide_share_ <= 1.f)) throw Error("internal: the guide's share lies in (0, 1]");
}

// The probability that a vertex in histogram h's cell gets a sample, and
// the guide's share of it. Mixed with another estimator, every vertex
// gets one, guide_share_ of them from the guide. Alone, a vertex gets one
// with the probability of its chain's share of the light the cell
// receives: a chain that brings little light there gets few samples.
GuidedEstimator::Mixture GuidedEstimator::mixture(int h) const {
    if (other_) return {1.f, guide_share_};
    return {guide_->share(h), 1.f};
}

// The other estimator's density of the path's direction, where it draws a
// share of the samples (for the cone it costs a ray query, its probe).
float GuidedEstimator::other_pdf(const Mixture& m, const PathToLight& path, PathCounters& counters) const {
    return other_ && m.guided < 1.f ? other_->pdf(path, counters) : 0.f;
}

LightSample GuidedEstimator::follow(const glm::vec3& p, const glm::vec3& w, SampleStream& rng,
                                    PathCounters& counters, PathToLight& path) const {
    switch (chain_) {
    case SpecularChain::Refraction: return light_through_refraction(scene_, p, w, rng, counters, &path);
    case SpecularChain::ReflectionRefraction: return through_reflection(p, w, rng, counters, path);
    case SpecularChain::RefractionReflection: return reflected_outside(p, w, rng, counters, path);
    case SpecularChain::None: break;
    }
    return {};
}

// The light leaving p along w by an internal reflection and the refraction
// out (render/specular_manifold.h follows the chain).
LightSample GuidedEstimator::through_reflection(const glm::vec3& p, const glm::vec3& w, SampleStream& rng,
                                                PathCounters& counters, PathToLight& path) const {
    ++counters.shadow_rays;
    const auto e = reflected_exit(scene_, p, w);
    if (!e || !(e->weight > 0.f)) return {};
    const Spectrum le = scene_.light.radiance_toward(e->exterior);
    if (!(max_component(le) > 0.f) || scene_.blocked(e->exit_point, e->exit.geometric_normal, e->exterior)) return {};
    path = PathToLight{p, w, e->exterior, SpecularChain::ReflectionRefraction, e->reflection_point, e->exit_point};
    LightSample ls;
    ls.radiance = e->weight * le;
    ls.transmittance = ratio_tracking(*scene_.medium, p, w, e->reflection.t, rng, counters);
    if (max_component(ls.transmittance) > 0.f)
        ls.transmittance *= ratio_tracking(*scene_.medium, e->reflection_point, e->reflected, e->exit.t, rng, counters);
    return ls;
}

// The light leaving p along w by the refraction out at y1 and a reflection
// off the outside at y2, where the refracted ray meets the object again:
// the glint the integrator counts when a path arrives there (enter()).
LightSample GuidedEstimator::reflected_outside(const glm::vec3& p, const glm::vec3& w, SampleStream& rng,
                                               PathCounters& counters, PathToLight& path) const {
    ++counters.shadow_rays;
    const auto exit = scene_.boundary->intersect(p, w, 0.f, kInfinity);
    if (!exit || glm::dot(w, exit->geometric_normal) <= 0.f) return {};
    const BoundaryTransmission out =
        boundary_transmission(scene_.interface, w, interface_normal(*exit, w, false), false);
    const glm::vec3& n1 = exit->geometric_normal;
    // Leaving a convex object, nothing meets it again (the integrator
    // does not ask either: a grazing ray could meet the next facet).
    if (!(out.weight > 0.f) || !on_sampled_side(w, out.direction, n1, false) || scene_.boundary->convex()) return {};
    const glm::vec3 y1 = p + exit->t * w, o = scene_.offset(y1, n1, out.direction);
    const auto other = scene_.boundary->intersect(o, out.direction, 0.f, kInfinity);
    if (!other || !(glm::dot(out.direction, other->geometric_normal) < 0.f)) return {};
    const glm::vec3 y2 = o + other->t * out.direction;
    const glm::vec3& n2 = other->geometric_normal;
    const glm::vec3 n = interface_normal(*other, out.direction, true);
    const float reflectance =
        1.f - boundary_transmission(scene_.interface, out.direction, n, true).weight;
    const glm::vec3 mirror = reflect(out.direction, glm::dot(out.direction, n) < 0.f ? n : -n);
    if (!(reflectance > 0.f) || !on_sampled_side(out.direction, mirror, n2, true)) return {};
    const Spectrum le = scene_.light.radiance_toward(mirror);
    if (!(max_component(le) > 0.f) || scene_.blocked(y2, n2, mirror)) return {};
    path = PathToLight{p, w, mirror, SpecularChain::RefractionReflection, y2, y1};
    LightSample ls;
    ls.radiance = out.weight * reflectance * le;
    ls.transmittance = ratio_tracking(*scene_.medium, p, w, exit->t, rng, counters);
    return ls;
}

std::optional<LightSample> GuidedEstimator::sample(const glm::vec3& p, float u1, float u2, SampleStream& rng,
                                                   PathCounters& counters) const {
    const int h = guide_->histogram(p, chain_);
    if (h < 0) return other_ ? other_->sample(p, u1, u2, rng, counters) : std::nullopt;
    const Mixture m = mixture(h);
    if (m.sampled < 1.f && !(rng.uniform() < m.sampled)) return std::nullopt;
    const LightGuide::Site site = guide_->site(h, p);
    if (m.guided >= 1.f || rng.uniform() < m.guided) {
        const glm::vec3 w = guide_->sample(site, u1, u2, rng.uniform());
        PathToLight path;
        LightSample ls = follow(p, w, rng, counters, path);
        ls.direction = w;
        if (!(max_component(ls.radiance) > 0.f)) return ls;  // nothing arrives: no density needed
        ls.pdf = density(site, m, w, other_pdf(m, path, counters));
        // A direction drawn on a bin's edge may round into an empty
        // neighbour: drop it (a density of 0 would read as a delta).
        if (!(ls.pdf > 0.f)) ls.radiance = Spectrum(0.f);
        return ls;
    }
    std::optional<LightSample> ls = other_->sample(p, u1, u2, rng, counters);
    if (ls && !ls->is_delta()) ls->pdf = density(site, m, ls->direction, ls->pdf);
    return ls;
}

float GuidedEstimator::pdf(const PathToLight& path, PathCounters& counters) const {
    if (path.chain != chain_) return 0.f;
    const int h = guide_->histogram(path.vertex, chain_);
    if (h < 0) return other_ ? other_->pdf(path, counters) : 0.f;
    const Mixture m = mixture(h);
    return density(guide_->site(h, path.vertex), m, path.direction, other_pdf(m, path, counters));
}

// The density of direction w at the guide's site: the guide's share of the
// samples from the guide, the rest from the other estimator (whose density
// of w is `other`).
float GuidedEstimator::density(const LightGuide::Site& site, const Mixture& m, const glm::vec3& w,
                               float other) const {
    return m.sampled * (m.guided * guide_->pdf(site, w) + (1.f - m.guided) * other);
}

}  // namespace jade
