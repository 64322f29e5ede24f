#pragma once
// Unbiased volumetric path tracing (docs/design.md, "Transport") through the
// dielectric boundary and the medium inside it.
//
// Free flights are sampled by delta tracking (Woodcock et al. 1965) against
// the medium's majorant segments (render/tracking.h). RGB media are
// chromatic, so each path has a hero channel, uniform (a pixel's samples
// take the channels in turn: render/pixel_sampler.h), draws its free
// flights against that channel's majorant and chooses its collision events
// (absorb / scatter / null) with that channel's probabilities (spectral
// tracking); the path's weight for each channel is then combined across
// the three channels' sampling densities by one-sample MIS with the balance
// heuristic (spectral MIS: Wilkie et al. 2014; pbrt-v4's VolPathIntegrator,
// Mitsuba 3's volpathmis). The estimate is unbiased in every channel and
// bounded: no channel's weight exceeds 3.
//
// Lights: the environment is met by rays leaving the scene, the directional
// light by rays leaving within its disc; both are also estimated at
// scattering vertices by the scene's light estimators (render/light_estimator.h),
// weighed against those hits by MIS: each light's heuristic of the two
// strategies' densities of a direction, times the channels' balance
// heuristic. Behind a dielectric, where each estimate follows the light
// through the boundary, the directional light is estimated at every one of
// a path's first scatterings and at a share of the later ones, each of
// those weighed by the share's inverse (MIS takes the share times the
// estimator's density).
// Where a ray from outside would reflect straight out of the scene, the
// reflection is counted at once and the refraction kept by roulette (enter()). What a camera ray
// that leaves without interacting sees (background, environment or nothing)
// is the renderer's to compose: the path returns its weight.
//
// Stiff media: where a homogeneous medium surrounds a path's vertex with a
// sphere of several mean free paths in every channel, the path crosses
// that sphere in one step drawn from a table of exact walks
// (render/sphere_exit.h, docs/stiff-media.md) instead of collision by
// collision, so an optically thick, bright object costs a bounded number
// of steps a path however many collisions its walk makes. The walk's
// collisions get no light estimate (the light reaching that deep is
// found by the path when it leaves, with full weight).
//
// Absorption weighs a path at each real collision (the walks through
// spheres excepted, which draw it). Paths end by Russian roulette (after
// `rr_depth` interactions, survival = throughput when below 1) or when they would make interaction
// max_depth + 1: the light reaching the first max_depth interactions is
// counted (a walk through a sphere counts as one interaction). A cap biases
// the image, so capped paths are counted for reports.

#include "jade/core/random.h"
#include "jade/render/light_estimator.h"
#include "jade/render/pixel_sampler.h"
#include "jade/render/scene.h"
#include "jade/render/sphere_exit.h"
#include "jade/render/tracking.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace jade {

// Next-event estimation of the directional light through a smooth boundary
// (render/light_estimator.h), each with MIS against disc hits: the manifold
// walk, the guided cone, or `Auto`, the one that converges faster for the
// light's size (the walk for small discs, the cone for wide ones; the bound
// is lower where the light guide is mixed in). Off, the
// light inside is found only by paths that happen to refract out into its
// disc: same mean, more noise (for tests and benchmarks of the strategies).
// A delta light is reached only by the manifold walk, whatever is chosen.
// An environment image is sampled through the boundary by the walk unless
// this is Off (render/light_estimator.h).
enum class LightThroughBoundary { Off, Auto, Cone, Manifold };
const char* to_string(LightThroughBoundary estimator);
// "auto", "manifold", "cone" or "off"; "true" and "false" (what older jobs
// stored) mean auto and off. Throws jade::Error naming --light-nee.
LightThroughBoundary parse_light_through_boundary(const std::string& name);
// The specular chains through the boundary along which the light
// estimators reach a light (render/light_estimators/manifold.h): one
// refraction (One), or also one internal reflection before it (Two). Auto
// takes Two for a delta light, which nothing else reaches along that chain
// (a delta light's second chain at a share of the vertices only,
// render/light_estimator.cpp);
// for a disc light with the light guide, the guide's own second chain
// (which beat the walk's at 5° on the demo); without it, Two for a disc
// small enough for the walk (under 10°, unless the cone is asked for), and
// One otherwise: on the demo at equal time the walk's second chain lowered
// the error at 5° and raised it under the 20° disc and the sunrise sky
// (README, "How the lights reach the inside"). One drops the guide's second
// chain too.
enum class LightChain { Auto, One, Two };
const char* to_string(LightChain chain);
// "auto", "1" or "2". Throws jade::Error naming --light-chain.
LightChain parse_light_chain(const std::string& name);

struct IntegratorSettings {
    int max_depth = 4096;  // surface + medium interactions; counted when reached
    int rr_depth = 8;      // interactions before Russian roulette starts
    LightThroughBoundary light_through_boundary = LightThroughBoundary::Auto;
    LightChain light_chain = LightChain::Auto;
    // Cross spheres of homogeneous medium in one step where they fit
    // (render/sphere_exit.h); off only to compare with collision-by-collision
    // tracking (tests, `bench stiff`).
    bool sphere_walks = true;
    // The share of medium vertices at which an environment image is
    // estimated through a dielectric boundary (the manifold walks; each
    // estimate then weighs 1/share, and MIS takes share × its density).
    // A walk costs about ten of the path's own steps in the fitted stone,
    // and paths find much of a sky by themselves: on the demo under an HDR
    // sky, 0.1 gave 2.4× lower error at equal time than 1 and 1.8× lower
    // than no estimate (docs/design.md, "Environment sampling").
    float environment_share = 0.1f;
    // The share of a path's later medium vertices (from its third
    // scattering) at which the directional light is estimated through a
    // dielectric boundary, chosen systematically along the path; each
    // estimate weighs 1/share, and MIS takes share × its density. The first
    // scatterings gather most of the light; at the later ones an estimate
    // costs more than the variance it takes away: on the demo, a delta
    // light's error² × time fell about a quarter, a 20° disc's relative MSE at
    // equal time 8 % (docs/design.md, "Light estimators"). 1: every vertex.
    float light_share = 0.4f;
    // Where a disc light is estimated through a refracting boundary, draw
    // half the estimator's directions from the light guide, which knows
    // every face the light comes in by (render/light_guide.h).
    bool light_guide = true;
    // The rays the guide traces from the light; a render sets it from its
    // camera samples (light_guide_photons in render/light_guide.h).
    std::uint32_t light_guide_photons = 1u << 18;
    // The guide, already traced for this scene, seed and ray count
    // (light_guide_for): a fit's renders of one size share all three, and
    // a fitting render of 24² spent a sixth of its time tracing the same
    // rays again. Null: the render traces its own.
    std::shared_ptr<const LightGuide> built_light_guide;
    void validate() const;
};

struct PathSample {
    Spectrum radiance{0.f};
    bool hit_object = false;    // the camera ray met the object (coverage)
    // A camera ray that left the scene without interacting (it may have
    // crossed an index-matched boundary): its weight and direction, for the
    // renderer to look up the backdrop. Zero weight otherwise.
    Spectrum backdrop_weight{0.f};
    glm::vec3 backdrop_direction{0.f};
};

class Integrator {
public:
    // The scene must outlive the integrator. The seed keys the sphere exit
    // tables a stiff homogeneous medium needs (built here, in parallel).
    Integrator(const Scene& scene, const IntegratorSettings& settings, std::uint64_t seed = 1);
    // Memory of those tables (0 when the scene needs none).
    std::size_t sphere_exit_bytes() const { return sphere_exits_.memory_bytes(); }
    // One camera path: radiance arriving at the camera along propagation
    // direction `direction` (unit) from `origin`, which lies outside the
    // object. Its first boundary query, from `origin` along `direction` over
    // (0, ∞), is answered already (camera rays are traced in packets,
    // MeshAccel::intersect_packet), and its hero channel and the numbers of
    // its first free flight drawn whole and its first scattering's direction
    // are the pixel's (render/pixel_sampler.h): each uniform on its own.
    PathSample trace(const glm::vec3& origin, const glm::vec3& direction,
                     const std::optional<SurfaceHit>& first_hit, int hero, const FirstNumbers& first,
                     SampleStream& rng, PathCounters& counters) const;

private:
    struct PathState;
    enum class Flight { Reached, Scattered, Ended };
    enum class Walk { NotTaken, Left, Ended };
    void follow(PathState& s, const std::optional<SurfaceHit>* first_hit) const;
    Walk walk_sphere(PathState& s) const;
    double sphere_room(PathState& s, const Spectrum& sigma_t) const;
    Flight track(PathState& s, MajorantTracker& tracker, float t_to, MediumProperties& at) const;
    Flight fly(PathState& s, std::optional<SurfaceHit>& hit, MediumProperties& at) const;
    Flight fly_drawn(PathState& s, std::optional<SurfaceHit>& hit, MediumProperties& at) const;
    std::optional<Flight> draw_flight(PathState& s, std::optional<SurfaceHit>& hit, MediumProperties& at) const;
    bool scatter(PathState& s, const MediumProperties& m) const;
    bool select_directional(PathState& s) const;
    void estimate_light(PathState& s, const LightEstimator& estimator, MisHeuristic heuristic, const glm::vec3& p,
                        float share = 1.f) const;
    bool cross_surface(PathState& s, const SurfaceHit& hit) const;
    std::optional<BoundarySample> enter(PathState& s, const glm::vec3& p, const glm::vec3& ng,
                                        const glm::vec3& n, float u) const;
    void split_reflection(PathState& s, const glm::vec3& p, const glm::vec3& ng, const glm::vec3& mirror,
                          float reflectance) const;
    void escape(PathState& s) const;
    Spectrum met_light(PathState& s, const DistantLight& light,
                       const std::vector<std::unique_ptr<LightEstimator>>& estimators, MisHeuristic heuristic,
                       float share, const glm::vec3& leaving, const ChainTracker& chain) const;
    bool survive(PathState& s) const;

    const Scene& scene_;
    IntegratorSettings settings_;
    LightEstimators estimators_;
    SphereExitTables sphere_exits_;
    std::array<bool, 3> draw_first_{false, false, false};  // per hero channel: fly_drawn
    // The directional light behind a dielectric: estimated at a share of the
    // later vertices, chosen systematically (select_directional).
    bool thin_directional_light_ = false;
};

}  // namespace jade
