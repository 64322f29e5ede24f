#include "jade/render/integrator.h"

#include "jade/core/error.h"
#include "jade/core/sampling.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace jade {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Crossings of an index-matched boundary are not interactions; a ray passing
// through more than this many surfaces is caught in a degenerate mesh.
constexpr int kMaxCrossings = 4096;

// Free-flight distance to the next tentative collision against majorant mu.
inline float sample_free_flight(float mu, SampleStream& rng) {
    return -std::log1p(-rng.uniform()) / mu;
}

// Leaves the surface at p on the side `direction` points to.
inline glm::vec3 offset_origin(const glm::vec3& p, const glm::vec3& ng, const glm::vec3& direction,
                               float eps) {
    return p + (glm::dot(direction, ng) > 0.f ? eps : -eps) * ng;
}

// Spectral MIS bookkeeping. beta is the path throughput divided by the hero
// channel's sampling density, r_u the ratio of each channel's density to the
// hero's; beta / average(r_u) is the balance-heuristic estimate. Both are
// rescaled together after every update (the quotient is unchanged) so that
// long paths neither overflow nor underflow: average(r_u) stays 1.
struct SpectralWeight {
    Spectrum beta{1.f};
    Spectrum r_u{1.f};

    void scale(const Spectrum& f) {
        beta *= f;
        r_u *= f;
        const float s = average(r_u);
        beta /= s;
        r_u /= s;
    }
    const Spectrum& throughput() const { return beta; }  // average(r_u) == 1
};

}  // namespace

void IntegratorSettings::validate() const {
    if (max_depth < 1) throw Error("--max-depth must be at least 1");
    if (rr_depth < 0) throw Error("--rr-depth must not be negative");
}

PathCounters& PathCounters::operator+=(const PathCounters& o) {
    paths += o.paths;
    real_collisions += o.real_collisions;
    null_collisions += o.null_collisions;
    surface_events += o.surface_events;
    shadow_rays += o.shadow_rays;
    capped_paths += o.capped_paths;
    return *this;
}

namespace {

// Ratio tracking (Cramer 1978; Novák et al. 2014) along o + t·d for
// 0 <= t < t_max: every tentative collision multiplies the estimate by the
// probability of a null collision there, σ_n / μ̄, per channel.
Spectrum ratio_tracking(const Medium& medium, float mu, const glm::vec3& o, const glm::vec3& d,
                        float t_max, SampleStream& rng, PathCounters& counters) {
    Spectrum tr(1.f);
    for (float t = sample_free_flight(mu, rng); t < t_max; t += sample_free_flight(mu, rng)) {
        const MediumProperties m = medium.at(o + t * d);
        ++counters.null_collisions;
        tr *= glm::max(Spectrum(0.f), Spectrum(1.f) - (m.sigma_s + m.sigma_a) / mu);
        // Russian roulette on a faint shadow ray keeps it unbiased and short.
        const float q = max_component(tr);
        if (q < 0.1f) {
            if (q <= 0.f || rng.uniform() >= q * 10.f) return Spectrum(0.f);
            tr /= q * 10.f;
        }
    }
    return tr;
}

// The interface normal a ray meets at a hit, as trace_path uses it: the
// shading normal bends the interface smoothly; where it faces away from the
// ray's side of the triangle, the triangle's own normal is used instead.
inline glm::vec3 interface_normal(const SurfaceHit& hit, const glm::vec3& d, bool entering) {
    return (glm::dot(d, hit.shading_normal) < 0.f) == entering ? hit.shading_normal
                                                               : hit.geometric_normal;
}

// Next-event estimation of the directional light through a smooth boundary.
// No straight shadow ray reaches a light behind a refracting surface, but a
// direction from a medium vertex can be chosen that will refract toward it:
// the guide is the interior direction that leaves along the light's axis
// through the surface point the axis itself meets (found by one probe ray),
// and directions are drawn uniformly from a cone of the light's angular
// radius around it. The sampled ray is then followed exactly: ratio-tracked
// to the boundary, refracted there with the interface's transmission weight,
// and counted if it leaves the scene inside the light's disc. The guide
// depends only on the vertex, so the cone's density is known for any
// direction and the estimate is combined with phase sampling (a path that
// scatters, refracts out once and escapes into the disc) by multiple
// importance sampling. It is a one-refraction special case of manifold
// next-event estimation (Hanika et al. 2015), kept unbiased by the exact
// tracing instead of a Newton solve.
struct LightGuide {
    glm::vec3 axis{0.f};
    float cos_max = 1.f;
    float pdf = 0.f;  // of every direction in the cone
    bool on = false;
    float pdf_of(const glm::vec3& w) const { return on && glm::dot(w, axis) >= cos_max ? pdf : 0.f; }
};

LightGuide light_guide(const Scene& scene, const glm::vec3& p) {
    LightGuide g;
    if (scene.interface.mode == BoundaryMode::Split && !(scene.interface.specular < 1.f))
        return g;  // a mirror: nothing leaves
    const glm::vec3& l = scene.light.direction();
    const auto probe = scene.boundary->intersect(p, l, 0.f, kInfinity);
    if (!probe || glm::dot(l, probe->geometric_normal) <= 0.f) return g;
    // Light arriving along -l refracts into the object (always possible from
    // the outside); the guide is its reverse.
    const BoundaryTransmission in =
        boundary_transmission(scene.interface, -l, interface_normal(*probe, -l, true), true);
    if (in.direction == glm::vec3(0.f)) return g;
    g.axis = -in.direction;
    g.cos_max = std::cos(scene.light.angular_radius_degrees() * 0.017453292519943295f);
    if (!(g.cos_max < 1.f)) return g;
    g.pdf = uniform_cone_pdf(g.cos_max);
    g.on = true;
    return g;
}

// The estimate itself, for medium vertex p with incoming direction d, phase
// sampling being the other strategy (balance heuristic).
Spectrum light_through_boundary(const Scene& scene, const LightGuide& g, const glm::vec3& p,
                                const glm::vec3& d, float mu, SampleStream& rng,
                                PathCounters& counters) {
    const float u1 = rng.uniform(), u2 = rng.uniform();
    if (!g.on) return Spectrum(0.f);
    ++counters.shadow_rays;
    const glm::vec3 w = uniform_cone(g.axis, g.cos_max, u1, u2);
    const auto hit = scene.boundary->intersect(p, w, 0.f, kInfinity);
    if (!hit || glm::dot(w, hit->geometric_normal) <= 0.f) return Spectrum(0.f);
    const BoundaryTransmission out =
        boundary_transmission(scene.interface, w, interface_normal(*hit, w, false), false);
    if (!(out.weight > 0.f)) return Spectrum(0.f);
    const float le = scene.light.radiance_toward(out.direction);
    if (!(le > 0.f)) return Spectrum(0.f);
    const glm::vec3 y = p + hit->t * w;
    if (scene.boundary->intersect(offset_origin(y, hit->geometric_normal, out.direction,
                                                scene.ray_epsilon),
                                  out.direction, 0.f, kInfinity))
        return Spectrum(0.f);  // the object itself is in the way
    const Spectrum tr = ratio_tracking(*scene.medium, mu, p, w, hit->t, rng, counters);
    const float f = scene.phase.eval(d, w);
    return tr * (f / (g.pdf + f) * out.weight * le);  // f/pdf times the MIS weight pdf/(pdf+f)
}

}  // namespace

Spectrum transmittance(const Scene& scene, const glm::vec3& origin, const glm::vec3& direction,
                       SampleStream& rng, PathCounters& counters) {
    ++counters.shadow_rays;
    Spectrum tr(1.f);
    const float mu = scene.medium ? max_component(scene.medium->majorant()) : 0.f;
    glm::vec3 o = origin;
    bool inside = true;  // shadow rays start at medium vertices
    for (int crossing = 0; crossing < kMaxCrossings; ++crossing) {
        const auto hit = scene.boundary->intersect(o, direction, 0.f, kInfinity);
        if (inside && mu > 0.f) {
            tr *= ratio_tracking(*scene.medium, mu, o, direction, hit ? hit->t : kInfinity, rng,
                                 counters);
            if (max_component(tr) <= 0.f) return tr;
        }
        if (!hit) return tr;
        const glm::vec3 p = o + hit->t * direction;
        inside = glm::dot(direction, hit->geometric_normal) < 0.f;
        o = offset_origin(p, hit->geometric_normal, direction, scene.ray_epsilon);
    }
    return Spectrum(0.f);
}

PathSample trace_path(const Scene& scene, const IntegratorSettings& settings,
                      const glm::vec3& origin, const glm::vec3& direction, float film_x,
                      float film_y, SampleStream& rng, PathCounters& counters) {
    ++counters.paths;
    PathSample out;
    const Medium* medium = scene.medium;
    const float mu = medium ? max_component(medium->majorant()) : 0.f;
    const bool index_matched = scene.interface.mode == BoundaryMode::None;
    const bool light_by_shadow_rays = index_matched && scene.light.on();
    const bool light_by_refraction = !index_matched && medium && settings.light_through_boundary &&
                                     scene.light.on() && !scene.light.is_delta();
    const int hero = std::min(2, int(3.f * rng.uniform()));

    SpectralWeight w;
    glm::vec3 o = origin, d = direction;
    bool inside = false;
    bool straight = true;        // still the camera ray (only index-matched crossings so far)
    bool light_counted = false;  // the last vertex counted the directional light by a shadow ray
    // Multiple importance sampling with light_through_boundary(): the weight
    // the light gets if this path, since its last scattering, refracts out
    // once and leaves the scene (mis_exit), which is the path class both
    // strategies sample. Any other event resets it to 1.
    float light_mis = 1.f;
    bool mis_pending = false, mis_exit = false;
    int depth = 0, crossings = 0;

    // Russian roulette after an interaction, only once the throughput has
    // fallen below 1 and with survival probability equal to it (pbrt-v4's
    // rule), so surviving weights stay at most 1. (A survival probability
    // capped below 1, as in Mitsuba, lets weights grow as 0.95^-n along the
    // long paths of bright media: unbiased, but heavy-tailed.)
    auto survive = [&]() {
        if (depth < settings.rr_depth) return true;
        const float q = max_component(w.throughput());
        if (q >= 1.f) return true;
        if (!(q > 0.f) || rng.uniform() >= q) return false;
        w.beta /= q;
        return true;
    };

    for (;;) {
        const auto hit = scene.boundary->intersect(o, d, 0.f, kInfinity);

        if (inside && mu > 0.f) {
            // Delta tracking to the next real collision before the boundary.
            const float t_max = hit ? hit->t : kInfinity;
            bool scattered = false;
            for (float t = sample_free_flight(mu, rng); t < t_max; t += sample_free_flight(mu, rng)) {
                const glm::vec3 p = o + t * d;
                const MediumProperties m = medium->at(p);
                const float p_absorb = m.sigma_a[hero] / mu;
                const float p_scatter = m.sigma_s[hero] / mu;
                const float xi = rng.uniform();
                if (xi < p_absorb) {  // absorbed: no emission, the path ends
                    ++counters.real_collisions;
                    return out;
                }
                if (xi < p_absorb + p_scatter) {
                    ++counters.real_collisions;
                    if (depth >= settings.max_depth) {  // one interaction too many
                        ++counters.capped_paths;
                        return out;
                    }
                    ++depth;
                    w.scale(m.sigma_s / m.sigma_s[hero]);
                    if (light_by_shadow_rays) {
                        float pdf;
                        const glm::vec3 wl = scene.light.sample(rng.uniform(), rng.uniform(), pdf);
                        const float li = scene.light.is_delta()
                                             ? scene.light.irradiance()
                                             : scene.light.disc_radiance() / pdf;
                        const Spectrum tr =
                            transmittance(scene, p, wl, rng, counters);
                        out.radiance += w.throughput() * scene.phase.eval(d, wl) * li * tr;
                    }
                    LightGuide guide;
                    if (light_by_refraction) {
                        guide = light_guide(scene, p);
                        out.radiance += w.throughput() *
                                        light_through_boundary(scene, guide, p, d, mu, rng, counters);
                    }
                    const glm::vec3 d_in = d;
                    o = p;
                    d = scene.phase.sample(d, rng.uniform(), rng.uniform());
                    if (guide.on) {
                        const float f = scene.phase.eval(d_in, d);
                        light_mis = f / (f + guide.pdf_of(d));
                    }
                    mis_pending = guide.on;
                    straight = false;
                    light_counted = light_by_shadow_rays;
                    scattered = true;
                    break;
                }
                // Null collision: continue with the null-collision weight.
                ++counters.null_collisions;
                const Spectrum sigma_n = glm::max(Spectrum(0.f), Spectrum(mu) - m.sigma_s - m.sigma_a);
                if (!(sigma_n[hero] > 0.f)) return out;  // probability-zero event (rounding)
                w.scale(sigma_n / sigma_n[hero]);
            }
            if (scattered) {
                if (!survive()) return out;
                continue;
            }
        }

        if (!hit) {  // the path leaves the scene
            Spectrum le(0.f);
            if (straight) {
                if (!scene.transparent)
                    le = scene.background ? scene.background->at(film_x, film_y)
                                          : scene.environment.radiance_toward(d);
            } else {
                le = scene.environment.radiance_toward(d);
                if (!light_counted)
                    le += Spectrum((mis_exit ? light_mis : 1.f) * scene.light.radiance_toward(d));
            }
            out.radiance += w.throughput() * le;
            return out;
        }

        if (straight) out.hit_object = true;
        const glm::vec3 p = o + hit->t * d;
        const glm::vec3& ng = hit->geometric_normal;
        const bool entering = glm::dot(d, ng) < 0.f;
        if (index_matched) {
            if (++crossings > kMaxCrossings) {
                ++counters.capped_paths;
                return out;
            }
        } else {
            if (depth >= settings.max_depth) {
                ++counters.capped_paths;
                return out;
            }
            ++depth;
            ++counters.surface_events;
            // The shading normal bends the interface smoothly; where it faces
            // away from the ray's side of the triangle, the triangle's own
            // normal is used instead.
            const glm::vec3& ns = hit->shading_normal;
            const glm::vec3 n = (glm::dot(d, ns) < 0.f) == entering ? ns : ng;
            const BoundarySample bs = sample_boundary(scene.interface, d, n, entering, rng.uniform());
            mis_exit = mis_pending && !entering && !bs.reflected;
            mis_pending = false;
            d = bs.direction;
            straight = false;
            light_counted = false;
            if (!survive()) return out;
        }
        // Which side the ray continues on decides whether it is in the medium.
        inside = glm::dot(d, ng) < 0.f;
        o = offset_origin(p, ng, d, scene.ray_epsilon);
    }
}

}  // namespace jade
