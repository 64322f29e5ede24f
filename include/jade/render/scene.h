#pragma once
// Everything a path needs to know about the world: the object's boundary and
// the medium inside it, the interface's optics, the phase function and the
// lights. The scene references its parts (mesh, medium, images); they must
// outlive it. Nothing here is global: a render is a function of its scene.

#include "jade/render/dielectric.h"
#include "jade/render/light.h"
#include "jade/render/medium.h"
#include "jade/geometry/mesh_accel.h"
#include "jade/render/phase_function.h"

namespace jade {

struct Scene {
    const MeshAccel* boundary = nullptr;   // the object's closed surface
    const Medium* medium = nullptr;        // what fills it (null: nothing, a glass shell)
    BoundaryParams interface;              // split / fresnel / none, IOR, specular
    PhaseFunction phase;
    DirectionalLight light;                // off by default
    Environment environment;               // black by default
    const Background* background = nullptr;  // seen by camera rays that miss, instead of the environment
    bool transparent = false;              // camera rays that miss see nothing (film alpha = coverage)
    // Offset of a ray leaving the surface, along the geometric normal, so it
    // cannot hit the triangle it leaves (1e-5 of the scene's size).
    float ray_epsilon = 1e-5f;

    // Sets ray_epsilon from the boundary's size; call after setting `boundary`.
    void fit_ray_epsilon();
};

}  // namespace jade
