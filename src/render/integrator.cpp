#include "jade/render/integrator.h"

#include "jade/core/error.h"
#include "jade/core/math.h"
#include "jade/core/sampling.h"
#include "jade/render/dielectric.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace jade {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Mean free paths, in the most transparent channel, that a sphere crossed
// in one step keeps from the surface: its collisions get no light estimate,
// and light from outside reaches that deep attenuated by e^-4 or more.
constexpr float kSphereMargin = 4.f;
// Mean free paths of the hero's majorant within which a flight through a
// heterogeneous medium asks for the surface first (Integrator::fly); 2 and
// 8 were slower on scenes A and B, measured before homogeneous media drew
// their flights first (Integrator::fly_drawn).
constexpr float kQueryReach = 4.f;

// A hero channel whose extinction varies by less than this fraction of its
// majorant draws its flights first (Integrator::fly_drawn): a drawn point is
// then a null collision with probability below it, and the one extra surface
// query such a point costs is rare. The default model's extinction is the
// same in every voxel (docs/design.md, "Coefficients") up to float rounding.
constexpr float kNearlyUniform = 1e-3f;

// Behind a dielectric the directional light is estimated at every one of a
// path's first kEstimatedVertices scatterings, and past them at a share of
// the vertices (IntegratorSettings::light_share), each estimate weighed by
// the share's inverse: a roulette of the estimate, unbiased; for a disc, MIS
// takes the share times the estimator's density, the probability density
// with which a vertex makes that direction. The first scatterings of a
// path gather most of its light (on the demo's vase, 88 % of what a delta
// light's walks find arrives through less than one mean free path). For a
// delta light (walks about four of the path's own steps each), on the
// demo's fitted volume in the vase (256², 128 spp, seeds 1 and 2;
// estimated error² × seconds, lower is better): every vertex 0.137; a share
// of 0.5 from the first 0.115, from the third 0.107 (0.4: 0.106, 0.3: 0.106,
// 0.2: 0.119), from the fifth 0.120. With the later vertices chosen
// systematically (Integrator::select_directional; relative MSE from three
// seeds × seconds, interleaved): 0.4 by coins 0.0174; systematically, 0.5
// 0.0171, 0.4 0.0149, 0.3 0.0151, 0.25 0.0156, 0.2 0.0154. For a 20° disc
// and the guide's estimators (256², 30 s, relative MSE from three seed
// pairs, interleaved): every vertex 0.00087, 0.4 from the third 0.00080;
// in another sitting every vertex 0.00094, 0.4 from the second 0.00086
// (docs/design.md, "Light estimators").
constexpr int kEstimatedVertices = 2;

// The sphere exit tables a scene needs: none unless the medium is
// homogeneous and spheres of level 1 fit in the object with their margin;
// levels up to the largest sphere a hero channel could use.
SphereExitTables sphere_exit_tables(const Scene& scene, const IntegratorSettings& settings,
                                    std::uint64_t seed) {
    if (!settings.sphere_walks || !scene.medium || !scene.medium->homogeneous()) return {};
    const MediumProperties m = scene.medium->at(glm::vec3(0.f));
    const Spectrum sigma_t = m.sigma_s + m.sigma_a;
    if (!(min_component(sigma_t) > 0.f)) return {};
    // No point inside a closed surface lies farther from it than half the
    // box's smallest side.
    const float deepest = 0.5f * min_component(scene.boundary->bounds().extent());
    const double largest = double(max_component(sigma_t)) *
                           double(deepest - kSphereMargin / min_component(sigma_t));
    // Unless a sphere of level 1 fits somewhere, the distance queries would
    // cost more than the few collisions level 0 saves.
    if (!(largest >= SphereExitTables::radius(1))) return {};
    return SphereExitTables(scene.phase, largest, seed);
}

// Spectral MIS bookkeeping (pbrt-v4's r_u / r_l). beta is the path
// throughput divided by the hero channel's sampling density; r_u holds each
// channel's density relative to the hero's, so beta / average(r_u) is the
// balance-heuristic estimate across channels. Both are rescaled together
// after every update (the quotients are unchanged) so that long paths
// neither overflow nor underflow: average(r_u) stays 1. A light reached by
// two strategies is weighed by mis_weight as well.
struct SpectralWeight {
    Spectrum beta{1.f};
    Spectrum r_u{1.f};

    void scale(const Spectrum& f) { scale(f, f); }
    // The contribution f and each channel's density relative to the hero's
    // differ where the event's probability is not its contribution.
    void scale(const Spectrum& f, const Spectrum& density) {
        beta *= f;
        r_u *= density;
        const float s = average(r_u);
        beta /= s;
        r_u /= s;
    }
};

}  // namespace

const char* to_string(LightThroughBoundary estimator) {
    switch (estimator) {
    case LightThroughBoundary::Off: return "off";
    case LightThroughBoundary::Auto: return "auto";
    case LightThroughBoundary::Cone: return "cone";
    case LightThroughBoundary::Manifold: return "manifold";
    }
    return "?";
}

LightThroughBoundary parse_light_through_boundary(const std::string& name) {
    if (name == "auto" || name == "true") return LightThroughBoundary::Auto;
    if (name == "manifold") return LightThroughBoundary::Manifold;
    if (name == "cone") return LightThroughBoundary::Cone;
    if (name == "off" || name == "false") return LightThroughBoundary::Off;
    throw Error("--light-nee must be 'auto', 'manifold', 'cone' or 'off', not '" + name + "'");
}

const char* to_string(LightChain chain) {
    switch (chain) {
    case LightChain::Auto: return "auto";
    case LightChain::One: return "1";
    case LightChain::Two: return "2";
    }
    return "?";
}

LightChain parse_light_chain(const std::string& name) {
    if (name == "auto") return LightChain::Auto;
    if (name == "1") return LightChain::One;
    if (name == "2") return LightChain::Two;
    throw Error("--light-chain must be 'auto', '1' or '2', not '" + name + "'");
}

void IntegratorSettings::validate() const {
    if (max_depth < 1) throw Error("--max-depth must be at least 1");
    if (rr_depth < 0) throw Error("internal: the Russian roulette depth must not be negative");
    if (light_guide_photons < 1) throw Error("internal: the light guide needs at least one ray");
    if (!(environment_share > 0.f && environment_share <= 1.f))
        throw Error("--env-share must lie in (0, 1]");
    if (!(light_share > 0.f && light_share <= 1.f)) throw Error("--light-share must lie in (0, 1]");
}

// Everything one path carries from event to event.
struct Integrator::PathState {
    PathState(const glm::vec3& origin, const glm::vec3& direction, SampleStream& r,
              PathCounters& c)
        : o(origin), d(direction), rng(r), counters(c) {}
    glm::vec3 o, d;
    SampleStream& rng;
    PathCounters& counters;
    int hero = 0;              // the channel whose probabilities choose collision events
    SpectralWeight w;
    bool inside = false;       // in the medium
    bool straight = true;      // still the camera ray (only index-matched crossings so far)
    // The ray starts on the surface going outward (a convex object is then
    // behind it for good: no query needed).
    bool left_surface = false;
    // What the path did since its last scattering, for MIS with the light
    // estimators (PathToLight): the specular chain so far, and that
    // scattering's vertex, direction and the phase function's density of it.
    ChainTracker chain;
    glm::vec3 scattered_at{0.f}, scattered_along{0.f};
    float phase_pdf = 0.f;
    // The probability that that scattering estimated the directional light
    // (Integrator::select_directional): MIS takes it times the estimator's
    // density of the direction.
    float directional_share = 1.f;
    int depth = 0, crossings = 0;
    int scatterings = 0;       // real collisions in a medium that scattered
    // The offset of the systematic selection of the later vertices that
    // estimate the directional light, drawn at the first of them; < 0 before.
    float later_offset = -1.f;
    glm::vec3 collision{0.f};  // where track() stopped at a real scattering
    float query_from = 0.f;    // the next surface query starts this far along the ray (Scene::spawn_inside)
    // The last exact distance to the surface and where it was asked
    // (negative: never), so sphere_room() need not ask again where it
    // cannot have grown enough.
    float surface_distance = -1.f;
    glm::vec3 distance_from{0.f};
    // The numbers the pixel gives the first free flight drawn whole and the
    // first scattering's direction (render/pixel_sampler.h), each taken once;
    // after that, and on paths without them, the stream's.
    FirstNumbers first;
    bool first_flight_unused = false;
    bool first_direction_unused = false;
    float flight_number() {
        if (!first_flight_unused) return rng.uniform();
        first_flight_unused = false;
        return first.flight;
    }
    std::array<float, 2> direction_numbers() {
        if (!first_direction_unused) {
            const float u1 = rng.uniform();
            return {u1, rng.uniform()};
        }
        first_direction_unused = false;
        return first.direction;
    }
    PathSample out;
};

Integrator::Integrator(const Scene& scene, const IntegratorSettings& settings, std::uint64_t seed)
    : scene_(scene), settings_(settings), estimators_(make_light_estimators(scene, settings, seed)) {
    settings_.validate();
    if (!scene.boundary) throw Error("internal: a scene needs a boundary mesh");
    sphere_exits_ = sphere_exit_tables(scene, settings_, seed);
    thin_directional_light_ = scene.light.on() && scene.medium && scene.interface.mode != BoundaryMode::None &&
                              settings_.light_share < 1.f;
    if (scene.medium) {
        const Spectrum mu = scene.medium->majorant(), floor = scene.medium->minorant();
        for (int c = 0; c < 3; ++c)
            draw_first_[c] = scene.medium->homogeneous() || mu[c] - floor[c] <= kNearlyUniform * mu[c];
    }
}

PathSample Integrator::trace(const glm::vec3& origin, const glm::vec3& direction,
                             const std::optional<SurfaceHit>& first_hit, int hero, const FirstNumbers& first,
                             SampleStream& rng, PathCounters& counters) const {
    if (hero < 0 || hero > 2) throw Error("internal: a hero channel is 0, 1 or 2");
    ++counters.paths;
    PathState s(origin, direction, rng, counters);
    s.hero = hero;
    s.first = first;
    s.first_flight_unused = true;
    s.first_direction_unused = true;
    follow(s, &first_hit);
    return s.out;
}

// The path from s on, until it ends. `first_hit`, when not null, answers
// its first boundary query (from outside: a camera ray's, from the caller).
void Integrator::follow(PathState& s, const std::optional<SurfaceHit>* first_hit) const {
    for (bool first = first_hit != nullptr;; first = false) {
        std::optional<SurfaceHit> hit;
        if (first) {
            hit = *first_hit;
        } else if (s.inside && scene_.medium) {
            const Walk walk = walk_sphere(s);
            if (walk == Walk::Ended) return;
            if (walk == Walk::Left) {
                if (!survive(s)) return;
                continue;
            }
            MediumProperties m;
            const Flight flight = fly(s, hit, m);
            if (flight == Flight::Ended) return;
            if (flight == Flight::Scattered) {
                if (!scatter(s, m) || !survive(s)) return;
                continue;
            }
        } else if (!(s.left_surface && scene_.boundary->convex())) {
            hit = scene_.boundary->intersect(s.o, s.d, 0.f, kInfinity);
        }
        if (!hit) {
            escape(s);
            return;
        }
        if (!cross_surface(s, *hit)) return;
    }
}

// The radius of a sphere about s.o that keeps kSphereMargin from the
// surface, in mean free paths of the hero channel, or a negative number when not even level 0's
// sphere fits. The clearance grid answers deep inside; nearer the surface an
// exact distance query does, and the distance being 1-Lipschitz, the last
// answer bounds the distance from above until the path has moved far enough
// for a sphere to fit.
double Integrator::sphere_room(PathState& s, const Spectrum& sigma_t) const {
    const float margin = kSphereMargin / min_component(sigma_t);
    const float mfp = 1.f / sigma_t[s.hero];
    const float need = margin + float(SphereExitTables::kSmallestRadius) * mfp;
    if (s.surface_distance >= 0.f && s.surface_distance + glm::length(s.o - s.distance_from) < need)
        return -1.0;
    // The grid's bound falls short of the distance by up to about a cell
    // and a half: within two cells of `need` the exact distance is asked,
    // in a ball that wide (a few triangles), so that the spheres near the
    // surface are as large as they may be.
    const float cell = scene_.boundary->clearance_resolution();
    float d = scene_.boundary->clearance(s.o);
    if (d < need + 2.f * cell) {
        d = scene_.boundary->distance_to_surface(s.o, need + 4.f * cell);
        s.surface_distance = d;
        s.distance_from = s.o;
    }
    if (!(d >= need)) return -1.0;
    // At least level 0's radius (σ_h·(need − margin) may round below it).
    return std::max(SphereExitTables::kSmallestRadius, double(sigma_t[s.hero]) * double(d - margin));
}

// Crossing a sphere of homogeneous medium in one step (render/sphere_exit.h):
// a stored walk of the sphere's level, turned about s.d by a random angle.
// Its n collisions and length L weigh the path: the hero survives the walk
// with its albedo^n (absorption drawn, not weighed as scatter() does: with
// n up to 10¹⁰ a weight would only be Russian roulette's to kill), and
// every channel's weight gains (σ_s/σ_s[h])^n for the scatterings and T/T[h] = e^(−(σ_t − σ_t[h]) L) for the flights, formed in
// logarithms (n reaches 10¹⁰ in the stiffest media we test). A walk with
// collisions leaves the last scattering unknown: the path then meets a light
// with full weight (ChainTracker::lose), no light estimate having been made there.
Integrator::Walk Integrator::walk_sphere(PathState& s) const {
    if (sphere_exits_.levels() == 0) return Walk::NotTaken;
    const MediumProperties m = scene_.medium->at(s.o);
    const Spectrum sigma_t = m.sigma_s + m.sigma_a;
    const int h = s.hero;
    const int level = sphere_exits_.level_for(sphere_room(s, sigma_t));
    if (level < 0) return Walk::NotTaken;
    const SphereExit& e = sphere_exits_.sample(level, s.rng.uniform());
    ++s.counters.sphere_walks;
    if (e.collisions > 0.0) {
        if (s.depth >= settings_.max_depth) {
            ++s.counters.capped_paths;
            return Walk::Ended;
        }
        ++s.depth;
        s.counters.real_collisions += std::uint64_t(e.collisions);
        const double albedo = double(m.sigma_s[h]) / double(sigma_t[h]);
        if (!(double(s.rng.uniform()) < std::exp(e.collisions * std::log(albedo)))) return Walk::Ended;
    }
    const double length = e.path_length / double(sigma_t[h]);
    double log_w[3];
    for (int c = 0; c < 3; ++c) {
        log_w[c] = -(double(sigma_t[c]) - double(sigma_t[h])) * length;
        if (e.collisions > 0.0) log_w[c] += e.collisions * std::log(double(m.sigma_s[c]) / double(m.sigma_s[h]));
    }
    const double top = std::max(log_w[0], std::max(log_w[1], log_w[2]));  // the hero's 0 at least
    s.w.scale(Spectrum(float(std::exp(log_w[0] - top)), float(std::exp(log_w[1] - top)),
                       float(std::exp(log_w[2] - top))));
    const float phi = 2.f * kPi * s.rng.uniform();
    const float c = std::cos(phi), sn = std::sin(phi);
    const float r = float(SphereExitTables::radius(level)) / sigma_t[h];
    const SphereExitFrame frame(s.d, c, sn);
    s.o += r * frame.to_world(e.point);
    s.d = glm::normalize(frame.to_world(e.direction));
    if (e.collisions > 0.0) {
        s.straight = false;
        s.chain.lose();
    }
    return Walk::Left;
}

// A free flight in the medium: first through the stretch the boundary's
// clearance proves free of the surface (no ray query; s.o advances), then,
// only if no real collision happened there, up to the boundary, whose hit is
// left in `hit`. One tracker walks the whole flight from its start, so the
// optical depth drawn for a collision carries across the stretches (free
// flights are memoryless: the split is unbiased either way).
Integrator::Flight Integrator::fly(PathState& s, std::optional<SurfaceHit>& hit,
                                   MediumProperties& at) const {
    if (draw_first_[s.hero]) return fly_drawn(s, hit, at);
    Flight flight = Flight::Reached;
    const glm::vec3 start = s.o;
    const float query_from = s.query_from;
    s.query_from = 0.f;  // this flight ends at a collision or at the surface: a new ray either way
    MajorantTracker tracker(*scene_.medium, start, s.d, s.hero, Spectrum(0.f));
    float flown = 0.f;  // from start to s.o
    advance_within_clearance(*scene_.boundary, s.o, s.d, [&](float r) {
        flight = track(s, tracker, flown + r, at);
        flown += r;
        return flight == Flight::Reached;
    });
    if (flight != Flight::Reached) return flight;
    const float from = std::max(0.f, query_from - flown);
    // The surface is asked for first within kQueryReach mean free paths of
    // the hero's majorant: Embree then prunes every part of the mesh
    // farther away (scenes A and B took about 15 % less time). With no
    // surface that near, that stretch is tracked, and only a flight that
    // gets through it (e^-4 of them in a homogeneous medium) asks beyond.
    const float reach = std::max(from, kQueryReach / scene_.medium->majorant()[s.hero]);
    std::optional<RayHit> surface = scene_.boundary->intersect_ray(s.o, s.d, from, reach);
    if (!surface && std::isfinite(reach)) {
        flight = track(s, tracker, flown + reach, at);
        if (flight != Flight::Reached) return flight;
        s.o += reach * s.d;
        flown += reach;
        surface = scene_.boundary->intersect_ray(s.o, s.d, 0.f, kInfinity);
    }
    // A ray from inside that meets no surface has slipped out through a crack
    // between triangles: the medium lies inside the mesh, so there is nothing
    // to track (an unbounded flight through a grid that is zero beyond its
    // edge would draw null collisions for ever) and the path escapes.
    if (surface) flight = track(s, tracker, flown + surface->t, at);
    if (flight != Flight::Reached) return flight;
    // Reaching the end has the hero's probability T_maj[h].
    const Spectrum T_rest = tracker.transmittance();
    s.w.scale(T_rest / T_rest[s.hero]);
    // Only a flight that gets there needs the surface's normals.
    if (surface) hit = scene_.boundary->surface(*surface);
    return flight;
}

// A free flight where the hero's σ_t is its majorant everywhere (a
// homogeneous medium, or the default model's grid, whose extinction is the
// same in every voxel): every tentative collision is real, so the flight's
// length t is drawn once, first. The clearance's stretches are crossed while
// t exceeds them (no collision in them, no numbers drawn), and past them the
// surface is asked for only up to what is left of t (as Mitsuba's
// homogeneous medium does): a query that short costs Embree less than one
// to kQueryReach mean free paths, and none asks again. The weights are
// track()'s, T_maj / T_maj[h] over the whole flight; where σ_t falls short
// of the majorant (by under kNearlyUniform) the drawn point is a null
// collision with track()'s probability and weight, and the flight goes on.
Integrator::Flight Integrator::fly_drawn(PathState& s, std::optional<SurfaceHit>& hit,
                                         MediumProperties& at) const {
    for (;;) {
        const std::optional<Flight> flight = draw_flight(s, hit, at);
        if (flight) return *flight;
    }
}

// One drawn flight of fly_drawn: its end, or nothing after a null collision
// (the path then stands at it, its weight updated).
std::optional<Integrator::Flight> Integrator::draw_flight(PathState& s, std::optional<SurfaceHit>& hit,
                                                          MediumProperties& at) const {
    const Spectrum mu = scene_.medium->majorant();
    float t = mu[s.hero] > 0.f ? free_flight(mu[s.hero], s.flight_number()) : kInfinity;
    const glm::vec3 start = s.o;
    const float query_from = s.query_from;
    s.query_from = 0.f;  // this flight ends at a collision or at the surface: a new ray either way
    float flown = 0.f;   // the stretches crossed
    const bool past_clearance = advance_within_clearance(*scene_.boundary, s.o, s.d, [&](float r) {
        if (t <= r) return false;
        t -= r;
        flown += r;
        return true;
    });
    std::optional<RayHit> surface;
    if (past_clearance) {
        const float from = std::max(0.f, query_from - glm::length(s.o - start));
        if (t > from) surface = scene_.boundary->intersect_ray(s.o, s.d, from, t);
    }
    const float travelled = flown + (surface ? surface->t : t);
    if (std::isfinite(travelled)) s.w.scale(majorant_transmittance_ratio(mu, travelled, s.hero));
    if (surface) {
        hit = scene_.boundary->surface(*surface);
        return Flight::Reached;
    }
    // No surface up to t: a collision, unless the path has slipped out of
    // the object (through a crack between triangles, or past a grazing edge
    // within a spawn offset) and t takes it beyond the mesh's bounds; it then
    // escapes, as fly() lets a ray that meets no surface (a walk outside
    // would scatter for ever: one path of 18 432 did, in the furnace at IOR
    // 10). One that stays within the bounds scatters outside until it leaves them.
    const glm::vec3 collision = s.o + t * s.d;
    if (!std::isfinite(t) || !scene_.boundary->bounds().contains(collision)) return Flight::Reached;
    at = scene_.medium->at(collision);
    const int h = s.hero;
    const Spectrum sigma_t = at.sigma_s + at.sigma_a;
    if (!(sigma_t[h] < mu[h]) || s.rng.uniform() * mu[h] < sigma_t[h]) {
        ++s.counters.real_collisions;
        s.collision = collision;
        return Flight::Scattered;
    }
    ++s.counters.null_collisions;
    const Spectrum sigma_n = glm::max(Spectrum(0.f), mu - sigma_t);
    if (!(sigma_n[h] > 0.f)) return Flight::Ended;
    s.w.scale(sigma_n / sigma_n[h]);
    s.o = collision;
    return std::nullopt;
}

// Delta tracking to the next real collision before t_to, against the
// hero's majorant, on the flight's tracker: a real collision (its point in
// s.collision, its coefficients in `at`; the path scatters there and its
// absorption is a weight, scatter()), a zero-probability null event (the
// path ends), or none (the flight reached t_to; its majorant transmittance
// stays in the tracker until the flight's end, fly()). Each event's weight
// per channel is its contribution over the hero's probability of making it,
// which is also each channel's density relative to the hero's: T_maj /
// T_maj[h] into s.w for the flight, σ_t / σ_t[h] as the density and σ_s /
// σ_t[h] as the contribution of the collision (scatter()).
Integrator::Flight Integrator::track(PathState& s, MajorantTracker& tracker, float t_to,
                                     MediumProperties& at) const {
    const int h = s.hero;
    Flight result = Flight::Reached;
    tracker.track_to(t_to, s.rng,
        [&](const glm::vec3& p, const MediumProperties& m, const Spectrum& mu, const Spectrum& T_maj) {
            const Spectrum sigma_t = m.sigma_s + m.sigma_a;
            if (s.rng.uniform() < sigma_t[h] / mu[h]) {  // a real collision
                ++s.counters.real_collisions;
                s.collision = p;
                at = m;
                s.w.scale(T_maj / T_maj[h]);
                result = Flight::Scattered;
                return false;
            }
            // Null collision: continue with the null-collision weight.
            ++s.counters.null_collisions;
            const Spectrum sigma_n = glm::max(Spectrum(0.f), mu - m.sigma_s - m.sigma_a);
            if (!(sigma_n[h] > 0.f)) {  // probability-zero event (rounding)
                result = Flight::Ended;
                return false;
            }
            s.w.scale(T_maj * sigma_n / (T_maj[h] * sigma_n[h]));
            return true;
        });
    return result;
}

// A real collision at s.collision: the path scatters with the weight
// σ_s / σ_t[h], its absorption a weight rather than a coin the hero flips.
// A path then ends only by Russian roulette (survive()), which spares the
// first rr_depth collisions: the light of short paths is counted without
// the variance of an all-or-nothing absorption (scenes A, B and C reach
// equal error in 10–25 % less time; docs/design.md, "Absorption as a
// weight"). Then the light estimators' samples and a new direction from
// the phase function. False when the path is cut by max_depth or carries
// nothing (a medium that only absorbs).
bool Integrator::scatter(PathState& s, const MediumProperties& m) const {
    if (s.depth >= settings_.max_depth) {  // one interaction too many
        ++s.counters.capped_paths;
        return false;
    }
    ++s.depth;
    const Spectrum sigma_t = m.sigma_s + m.sigma_a;
    s.w.scale(m.sigma_s / sigma_t[s.hero], sigma_t / sigma_t[s.hero]);
    if (!(max_component(s.w.beta) > 0.f)) return false;
    if (select_directional(s))
        for (const auto& e : estimators_.directional)
            estimate_light(s, *e, estimators_.directional_mis, s.collision, s.directional_share);
    for (const auto& e : estimators_.environment) estimate_light(s, *e, estimators_.environment_mis, s.collision);
    const glm::vec3 d_in = s.d;
    s.o = s.collision;
    // An isotropic direction does not depend on the incoming one: drawn in
    // the world's frame, it needs no basis built about d_in (scenes A and B
    // took 2.5–4 % less time). The pixel's stratified numbers keep d_in's
    // frame, where their strata part the directions back toward the surface
    // the camera ray came in by from those going deeper.
    const bool stratified = s.first_direction_unused;
    const std::array<float, 2> u = s.direction_numbers();
    s.d = scene_.phase.isotropic() && !stratified ? uniform_sphere(u[0], u[1])
                                                  : scene_.phase.sample(d_in, u[0], u[1]);
    s.straight = false;
    s.chain.scattered();
    s.scattered_at = s.collision;
    s.scattered_along = s.d;
    s.phase_pdf = scene_.phase.eval(d_in, s.d);
    return true;
}

// Whether this scattering estimates the directional light, and with which
// probability (s.directional_share): 1 at every vertex, unless the light is
// behind a dielectric (thin_directional_light_); then 1 at the first
// kEstimatedVertices, and past them the share (IntegratorSettings::
// light_share) at the vertices a systematic selection picks. Each later
// vertex is picked with that probability, as by a coin, but a path makes
// ⌊n·q⌋ or ⌈n·q⌉ estimates over n of them, where coins would spread that
// count by n·q·(1 − q): on the demo's final job (256², 128 spp, three seeds)
// the relative MSE fell from 0.00125 to 0.00110 at the same walks.
bool Integrator::select_directional(PathState& s) const {
    s.directional_share = 1.f;
    if (!thin_directional_light_ || ++s.scatterings <= kEstimatedVertices) return true;
    if (s.later_offset < 0.f) s.later_offset = s.rng.uniform();
    const int later = s.scatterings - kEstimatedVertices - 1;
    s.directional_share = settings_.light_share;
    return systematic_selected(s.later_offset, later, settings_.light_share);
}

// Next-event estimation from medium vertex p with one estimator, made there
// with probability `share` (select_directional). Its density of its
// direction times the share, and the phase function's, give its MIS weight
// by the light's heuristic (mis_weight); for a path that later meets the
// light by itself, the estimator's density is asked at escape(). A delta
// sample (no path meets its light) weighs 1/share.
void Integrator::estimate_light(PathState& s, const LightEstimator& estimator, MisHeuristic heuristic,
                                const glm::vec3& p, float share) const {
    const float u1 = s.rng.uniform(), u2 = s.rng.uniform();
    const auto ls = estimator.sample(p, u1, u2, s.rng, s.counters);
    if (!ls || !(max_component(ls->radiance) > 0.f)) return;
    const float f = scene_.phase.eval(s.d, ls->direction);
    const Spectrum arriving = ls->radiance * ls->transmittance;
    const float pdf = share * ls->pdf;  // 0 for a delta sample
    if (ls->is_delta())
        s.out.radiance += s.w.beta * f * arriving / share;
    else if (estimator.hits() == LightHits::Excluded)
        s.out.radiance += s.w.beta * f * arriving / pdf;
    else  // f is the phase function's density of the direction too
        s.out.radiance +=
            s.w.beta * f * arriving * (mis_weight(heuristic, pdf, f) / (pdf * average(s.w.r_u)));
}

// The boundary at `hit`: crossed as if absent when index-matched, otherwise
// reflected or refracted. False when the path ends there: by roulette, at
// the depth cap, or where the shading normal sent it to the wrong side of
// the triangle (on_sampled_side).
bool Integrator::cross_surface(PathState& s, const SurfaceHit& hit) const {
    if (s.straight) s.out.hit_object = true;
    const glm::vec3 p = s.o + hit.t * s.d;
    const glm::vec3& ng = hit.geometric_normal;
    const bool entering = glm::dot(s.d, ng) < 0.f;
    if (scene_.interface.mode == BoundaryMode::None) {
        if (++s.crossings > kMaxCrossings) {
            ++s.counters.capped_paths;
            return false;
        }
    } else {
        if (s.depth >= settings_.max_depth) {
            ++s.counters.capped_paths;
            return false;
        }
        ++s.depth;
        ++s.counters.surface_events;
        const glm::vec3 n = interface_normal(hit, s.d, entering);
        const float u = s.rng.uniform();
        const std::optional<BoundarySample> sampled =
            entering ? enter(s, p, ng, n, u) : sample_boundary(scene_.interface, s.d, n, false, u);
        if (!sampled) return false;
        const BoundarySample& bs = *sampled;
        if (!on_sampled_side(s.d, bs.direction, ng, bs.reflected)) return false;  // a leak
        s.chain.record(p, entering, bs.reflected, glm::dot(bs.direction, ng) < 0.f);
        s.d = bs.direction;
        s.straight = false;
        if (!survive(s)) return false;
    }
    // Which side the ray continues on decides whether it is in the medium.
    s.inside = glm::dot(s.d, ng) < 0.f;
    s.left_surface = glm::dot(s.d, ng) > 0.f;
    if (s.inside) {
        const Scene::Spawn spawn = scene_.spawn_inside(p, ng, s.d);
        s.o = spawn.origin;
        s.query_from = spawn.query_from;
    } else {
        s.o = scene_.offset(p, ng, s.d);
    }
    return true;
}

// A ray arriving from outside at surface point p. Where its mirror image
// leaves the scene at once (a camera ray's glint of the sky or the light),
// the reflection's radiance is added with the reflectance as its weight
// (next-event estimation of a specular event: the direction is known), and
// the path goes on by the refraction with the transmittance as its weight.
// Where the mirror image meets the object again (a camera ray into the
// vase's mouth, between a handle and the body), a camera ray follows both
// branches, each with its weight (split_reflection). Choosing a branch at
// random instead gives every sample either the reflection's or the
// refraction's light at twice its weight: at probability 0.5 that coin
// alone adds a relative variance of 1 per camera sample (about 3.3 in all
// on the demo), and keeping the refraction by
// Russian roulette instead of by its weight cost 15 % more time to equal
// error, although half the camera paths then skip the medium (docs/design.md,
// "Boundary"). A path that has scattered still picks one branch where the
// mirror image meets the object: its light is the estimators' to find.
// nullopt: the path ends.
std::optional<BoundarySample> Integrator::enter(PathState& s, const glm::vec3& p, const glm::vec3& ng,
                                                const glm::vec3& n, float u) const {
    const BoundaryTransmission t = boundary_transmission(scene_.interface, s.d, n, true);
    const glm::vec3 mirror = reflect(s.d, glm::dot(s.d, n) < 0.f ? n : -n);
    const bool reflects = t.weight < 1.f && on_sampled_side(s.d, mirror, ng, true);
    if (!reflects) return sample_boundary(scene_.interface, s.d, n, true, u);
    if (!scene_.blocked(p, ng, mirror)) {
        ++s.counters.shadow_rays;
        // After one refraction out since the last scattering, the light's part
        // is a path the guided estimator makes too (light_estimators/guided.h):
        // weighed by MIS against it. No estimator makes any other path that
        // reflects off the outside (ChainTracker::glint classes them so).
        s.out.radiance += s.w.beta * (1.f - t.weight) *
                          (scene_.environment.radiance_toward(mirror) +
                           met_light(s, scene_.light, estimators_.directional, estimators_.directional_mis,
                                     s.directional_share, mirror, s.chain.glint(p)));
    } else if (s.straight) {
        split_reflection(s, p, ng, mirror, 1.f - t.weight);
    } else {
        return sample_boundary(scene_.interface, s.d, n, true, u);
    }
    if (!(t.weight > 0.f)) return std::nullopt;
    s.w.scale(Spectrum(t.weight), Spectrum(1.f));  // a weight, not a sampled event
    return BoundarySample{t.direction, false};
}

// The reflected branch of a camera ray at p, followed as a path of its own
// with the reflectance as its weight; its light is added to the ray's.
void Integrator::split_reflection(PathState& s, const glm::vec3& p, const glm::vec3& ng, const glm::vec3& mirror,
                                  float reflectance) const {
    PathState r = s;
    r.out = PathSample{};
    r.first_flight_unused = false;  // the refracted branch's
    r.first_direction_unused = false;
    r.w.scale(Spectrum(reflectance), Spectrum(1.f));
    r.chain.record(p, true, true, false);
    r.d = mirror;
    r.straight = false;
    r.inside = false;
    r.left_surface = true;
    r.o = scene_.offset(p, ng, mirror);
    follow(r, nullptr);
    s.out.radiance += r.out.radiance;
}

// The path leaves the scene: the environment and the directional light,
// each weighed against its estimator; a camera ray's backdrop is left to
// the renderer.
void Integrator::escape(PathState& s) const {
    if (s.straight) {
        s.out.backdrop_weight = s.w.beta;
        s.out.backdrop_direction = s.d;
        return;
    }
    s.out.radiance +=
        s.w.beta *
        (met_light(s, scene_.environment, estimators_.environment, estimators_.environment_mis, 1.f, s.d, s.chain) +
         met_light(s, scene_.light, estimators_.directional, estimators_.directional_mis, s.directional_share, s.d,
                   s.chain));
}

// The radiance a path leaving along `leaving` by `chain` (since the last
// scattering) counts from `light`: all of it, unless an estimator could
// have made the path too; then none (LightHits::Excluded) or phase
// sampling's share by the light's heuristic (mis_weight) from the
// estimator's and the phase function's densities of the scattering's
// direction (the events since the scattering, null collisions and the
// specular chain, scale both strategies' densities alike); the estimator's
// times `share`, the probability that the scattering estimated the light.
// The estimators' path classes are disjoint: at most one has a density here.
Spectrum Integrator::met_light(PathState& s, const DistantLight& light,
                               const std::vector<std::unique_ptr<LightEstimator>>& estimators,
                               MisHeuristic heuristic, float share, const glm::vec3& leaving,
                               const ChainTracker& chain) const {
    const Spectrum L = light.radiance_toward(leaving);
    if (!(max_component(L) > 0.f)) return Spectrum(0.f);
    const std::optional<SpecularChain> made = chain.chain();
    if (estimators.empty() || !made) return L;
    PathToLight path;
    path.vertex = s.scattered_at;
    path.direction = s.scattered_along;
    path.leaving = leaving;
    path.chain = *made;
    path.reflection = chain.reflection();
    path.exit = chain.exit();
    for (const auto& estimator : estimators) {
        const float pdf_light = share * estimator->pdf(path, s.counters);
        if (!(pdf_light > 0.f)) continue;
        if (estimator->hits() == LightHits::Excluded) return Spectrum(0.f);
        return L * (mis_weight(heuristic, s.phase_pdf, pdf_light) / average(s.w.r_u));
    }
    return L;
}

// Russian roulette after an interaction, only once the throughput has fallen
// below 1 and with survival probability equal to it (pbrt-v4's rule), so
// surviving weights stay at most 1. (A survival probability capped below 1,
// as in Mitsuba, lets weights grow as 0.95^-n along the long paths of bright
// media: unbiased, but heavy-tailed.)
bool Integrator::survive(PathState& s) const {
    if (s.depth < settings_.rr_depth) return true;
    const float q = max_component(s.w.beta);
    if (q >= 1.f) return true;
    if (!(q > 0.f) || s.rng.uniform() >= q) return false;
    s.w.beta /= q;
    return true;
}

}  // namespace jade
