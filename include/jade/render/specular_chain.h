#pragma once
// The specular events a path meets between a medium scattering vertex and a
// light at infinity: the light estimators' path classes (docs/design.md,
// "Light estimators"). The integrator records a phase-sampled path's events
// one by one, so that a path that meets the light is weighed against the
// one estimator that makes paths of its class, and against none when no
// estimator makes it.

#include <glm/vec3.hpp>

#include <optional>

namespace jade {

// None: index-matched crossings only. Refraction: one refraction out.
// ReflectionRefraction: one internal reflection, then the refraction out.
// RefractionReflection: the refraction out, then a reflection off the
// outside of another part of the object (a vase's handle mirrored in its
// neck).
enum class SpecularChain { None, Refraction, ReflectionRefraction, RefractionReflection };

class ChainTracker {
public:
    // Default: no scattering vertex known (a camera path, or a walk through
    // a sphere whose collisions left the last scattering unknown).
    ChainTracker() = default;
    // A scattering: nothing since (null collisions only).
    void scattered() { state_ = State::Straight; }
    // The last scattering is no longer known (a walk through a sphere made
    // collisions): what follows is no estimator's until the next one.
    void lose() { state_ = State::Other; }
    // A reflection or refraction at surface point p. `entering`: the ray
    // arrived from outside; `inside_after`: it continues inside.
    void record(const glm::vec3& p, bool entering, bool reflected, bool inside_after);
    // The chain of a ray that, arriving from outside at p, reflects off it
    // and leaves the scene at once (the glint Integrator::enter counts with
    // the reflectance as its weight): RefractionReflection after exactly
    // one refraction out, Other after anything else. The path itself goes
    // on by the refraction in and records that.
    ChainTracker glint(const glm::vec3& p) const;
    // The class of the chain so far, for a path that leaves the scene now;
    // nullopt when no estimator makes it (no scattering known, a reflection
    // inside that has not got out, or any other chain).
    std::optional<SpecularChain> chain() const;
    // Where the chain reflected (inside, or outside after the exit) and
    // where it refracted out, for the classes that have them.
    const glm::vec3& reflection() const { return reflection_; }
    const glm::vec3& exit() const { return exit_; }

private:
    enum class State { Other, Straight, Refracted, Reflected, ReflectedRefracted, RefractedReflected };
    State state_ = State::Other;
    glm::vec3 reflection_{0.f}, exit_{0.f};
};

}  // namespace jade
