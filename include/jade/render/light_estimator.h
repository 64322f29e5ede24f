#pragma once
// Light estimators: ways to find a light at infinity (the directional light
// or the environment image) from a medium scattering vertex other than
// waiting for a phase-sampled path to meet it (docs/design.md, "Light
// estimators"). Each one samples a direction at the vertex toward the light
// and follows it there; the integrator weighs its estimate against phase
// sampling by multiple importance sampling (each light's heuristic,
// LightEstimators) through the density of that direction.
//
// Variants live in render/light_estimators/:
//   shadow_ray      straight shadow rays through an index-matched boundary
//   refracted_cone  through a smooth dielectric, the directional light's
//                   disc only: a cone aimed so that it refracts toward the
//                   disc, MIS-weighted against paths that leave by one
//                   refraction
//   manifold        through a smooth dielectric: a direction drawn from the
//                   light (a point of the disc, the delta light's one
//                   direction, or the environment's importance sampling),
//                   and the specular chain to it (one refraction, or an
//                   internal reflection and then the refraction) found by
//                   Newton's method on the surface
//                   (render/specular_manifold.h)
//   guided          through a smooth dielectric, the directional light's
//                   disc only: directions from the light guide
//                   (render/light_guide.h), along any of its three chains
//                   (render/specular_chain.h), mixed with the cone or the
//                   walk where they cover one
// Without one, a light is found only by paths that meet it.

#include "jade/core/random.h"
#include "jade/core/sampling.h"
#include "jade/core/spectrum.h"
#include "jade/render/light.h"
#include "jade/render/specular_chain.h"
#include "jade/render/tracking.h"

#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace jade {

class LightGuide;

// How a phase-sampled path that meets the light by itself counts it, when
// the estimator could have made that path too (its pdf() is not 0).
enum class LightHits {
    Excluded,  // none: the estimator's samples count all of that light
    Weighted,  // by MIS against the estimator's density of it
};

// A sampled direction toward the light from a medium vertex and what
// arrives along it: the light's radiance times the boundary's transmission
// weight on the way, and the medium's transmittance. `pdf` is the
// direction's solid-angle density at the vertex; 0 marks a delta sample, for
// which `radiance` is already the integral over the delta (an irradiance at
// the vertex). Radiance 0 when the way is blocked.
struct LightSample {
    glm::vec3 direction{0.f};
    float pdf = 0.f;
    Spectrum radiance{0.f};
    Spectrum transmittance{0.f};
    bool is_delta() const { return !(pdf > 0.f); }
};

// A phase-sampled path from medium vertex `vertex` along `direction` that
// left the scene along `leaving` with nothing on the way but null
// collisions and the specular events of `chain` (for None, leaving =
// direction).
struct PathToLight {
    glm::vec3 vertex{0.f}, direction{0.f}, leaving{0.f};
    SpecularChain chain = SpecularChain::None;
    glm::vec3 reflection{0.f};  // where it reflected: inside, or outside after the exit
    glm::vec3 exit{0.f};        // where it refracted out
};

class LightEstimator {
public:
    explicit LightEstimator(const DistantLight& light) : light_(light) {}
    virtual ~LightEstimator() = default;
    // The light this estimator finds.
    const DistantLight& light() const { return light_; }
    // A direction from medium vertex p (none: this estimator finds nothing
    // from p). u1, u2 uniform in [0, 1); rng for ratio tracking.
    virtual std::optional<LightSample> sample(const glm::vec3& p, float u1, float u2,
                                              SampleStream& rng, PathCounters& counters) const = 0;
    // The density with which sample(path.vertex) makes path.direction, for
    // a path that met the light by itself; 0 when it cannot make that path.
    virtual float pdf(const PathToLight& path, PathCounters& counters) const = 0;
    virtual LightHits hits() const = 0;

protected:
    const DistantLight& light_;
};

// How a light's estimates and the paths that meet it by themselves share a
// direction both strategies make: by the balance heuristic of their
// densities of it, or by the power heuristic with exponent 2 (Veach 1997,
// §9.2.4), which gives less weight to the strategy that makes it rarely.
enum class MisHeuristic { Balance, Power };
// The weight of the strategy whose density of the direction is pdf_this,
// against the other's pdf_other (both > 0). A path's density by either
// strategy is one path prefix (each channel's r_u) times that strategy's
// density of the direction, so the channels' balance heuristic and this
// weight multiply into weights that sum to one over every channel and
// strategy.
float mis_weight(MisHeuristic heuristic, float pdf_this, float pdf_other);

struct IntegratorSettings;
// The estimators a scene calls for, for its directional light and for its
// environment (none: that light is found by paths that meet it). The path
// classes of one light's estimators are disjoint, so each path is weighed
// by MIS against phase sampling and at most one estimator. The scene must
// outlive them. Each light has its heuristic (docs/design.md, "Light
// estimators"): the power heuristic for the directional light's disc,
// whose guide draws most directions where its light is (on the demo at
// 20°, relative MSE 4.5 % lower than with the balance heuristic, at 5°
// 2 %); the balance heuristic for an environment image, whose walks are
// made at a tenth of the vertices (under Blender's sunrise sky the power
// heuristic's was 4 % higher).
struct LightEstimators {
    std::vector<std::unique_ptr<LightEstimator>> directional, environment;
    MisHeuristic directional_mis = MisHeuristic::Power, environment_mis = MisHeuristic::Balance;
};
// `seed` keys the light guide's tracing (render/light_guide.h).
LightEstimators make_light_estimators(const Scene& scene, const IntegratorSettings& settings,
                                      std::uint64_t seed);

// The light guide a render of `scene` with these settings and seed uses
// (its settings.light_guide_photons rays, traced from `seed`; or
// settings.built_light_guide as it is), or null where its estimators use
// none: a disc light behind a dielectric boundary, estimated.
std::shared_ptr<const LightGuide> light_guide_for(const Scene& scene, const IntegratorSettings& settings,
                                                  std::uint64_t seed);

}  // namespace jade
