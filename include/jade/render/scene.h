#pragma once
// Everything a path needs to know about the world: the object's boundary and
// the medium inside it, the interface's optics, the phase function and the
// lights. The scene references its parts (mesh, medium, images); they must
// outlive it. Nothing here is global: a render is a function of its scene.

#include "jade/render/dielectric.h"
#include "jade/render/light.h"
#include "jade/render/medium.h"
#include "jade/geometry/boundary.h"
#include "jade/render/phase_function.h"

#include <glm/geometric.hpp>

#include <limits>

namespace jade {

struct Scene {
    const Boundary* boundary = nullptr;    // the object's closed surface (a mesh or a sphere)
    const Medium* medium = nullptr;        // what fills it (null: nothing, a glass shell)
    BoundaryParams interface;              // split / fresnel / none, IOR, specular
    PhaseFunction phase;
    DirectionalLight light;                // off by default
    Environment environment;               // black by default
    // Offset of a ray leaving the surface, along the geometric normal, so it
    // cannot hit the triangle it leaves (1e-5 of the scene's size).
    float ray_epsilon = 1e-5f;

    // Sets ray_epsilon from the boundary's size; call after setting `boundary`.
    void fit_ray_epsilon();
    // Where a ray leaving surface point p (geometric normal ng) toward
    // `direction` starts: pushed off the surface to the side it goes.
    glm::vec3 offset(const glm::vec3& p, const glm::vec3& ng, const glm::vec3& direction) const {
        return p + (glm::dot(direction, ng) > 0.f ? ray_epsilon : -ray_epsilon) * ng;
    }
    // Whether the object is in the way of a ray leaving surface point y
    // (geometric normal ng) along exterior direction d: the shadow test of
    // every light path that leaves the object. Nothing meets a convex
    // object again once it has left it.
    bool blocked(const glm::vec3& y, const glm::vec3& ng, const glm::vec3& d) const {
        if (glm::dot(d, ng) > 0.f && boundary->convex()) return false;
        return boundary->occluded(offset(y, ng, d), d, 0.f, std::numeric_limits<float>::infinity());
    }
    // A ray leaving surface point p into the object (against outward ng)
    // along unit `direction`: the offset point lies ray_epsilon below the
    // surface, and a medium tracked from there would begin a layer that
    // thick too deep (σ_t·ε mean free paths: five in the unit sphere at
    // σ_t = 10⁵, which darkened a bright stiff object by 7 %). The ray
    // starts instead on the surface's plane, back along the ray from the
    // offset point, and the surface query skips `query_from` of it (the
    // stretch up to the offset point). A ray within 1/16 of grazing keeps the
    // offset point (the way back would cross too much of the surface).
    struct Spawn {
        glm::vec3 origin;
        float query_from = 0.f;
    };
    Spawn spawn_inside(const glm::vec3& p, const glm::vec3& ng, const glm::vec3& direction) const {
        const glm::vec3 o = offset(p, ng, direction);
        const float back = ray_epsilon / -glm::dot(direction, ng);
        if (!(back > 0.f && back <= 16.f * ray_epsilon)) return {o, 0.f};
        return {o - back * direction, back};
    }
};

}  // namespace jade
