#pragma once
// Sampling warps shared by the phase functions, the lights and the light
// estimators: uniform numbers in [0, 1)² → directions, with their densities;
// and the systematic selection of events along a path.

#include <glm/vec3.hpp>

namespace jade {

// A right-handed orthonormal frame (b1, b2, n) around unit vector n
// (Duff et al. 2017, "Building an orthonormal basis, revisited").
void orthonormal_basis(const glm::vec3& n, glm::vec3& b1, glm::vec3& b2);

// Direction uniform over the unit sphere (density 1/(4π)), in the world's
// frame: z = 1 − 2·u1 and the azimuth 2π·u2.
glm::vec3 uniform_sphere(float u1, float u2);

// Direction uniform in solid angle over the cone of unit `axis` with half-angle
// acos(cos_max), cos_max < 1; and that density, 1 / (2π (1 − cos_max)).
glm::vec3 uniform_cone(const glm::vec3& axis, float cos_max, float u1, float u2);
float uniform_cone_pdf(float cos_max);

// A cone of directions, uniform in solid angle. A delta cone (cos_max = 1) is
// one direction, whose density is a Dirac: an estimate that samples it is not
// divided by a density, and no other strategy can produce that direction.
struct UniformCone {
    glm::vec3 axis{0.f, 0.f, 1.f};
    float cos_max = 1.f;
    bool is_delta() const { return !(cos_max < 1.f); }
    // Density of direction w: 0 outside the cone, and for a delta cone.
    float pdf(const glm::vec3& w) const;
    // A direction of the cone and its density (1 for a delta cone).
    glm::vec3 sample(float u1, float u2, float& pdf) const;
};

// Directions uniform over an ellipse on the plane tangent to the unit
// sphere at `axis` (the gnomonic projection: w = normalize(axis + X·major
// + Y·minor) for (X/r_major)² + (Y/r_minor)² ≤ 1), major and minor
// orthonormal and perpendicular to axis. A cone with an elliptic section,
// the shape a small disc's directions take through a refracting surface.
// Its density in solid angle is 1 / (π r_major r_minor cos³θ), θ the angle
// from the axis: a solid angle dω at θ covers dω / cos³θ of the plane.
struct EllipticCone {
    glm::vec3 axis{0.f, 0.f, 1.f}, major{1.f, 0.f, 0.f}, minor{0.f, 1.f, 0.f};
    float r_major = 0.f, r_minor = 0.f;
    // Density of direction w: 0 outside the cone.
    float pdf(const glm::vec3& w) const;
    // A direction of the cone from u1, u2 in [0, 1).
    glm::vec3 sample(float u1, float u2) const;
};

// Systematic selection (systematic sampling, Madow and Madow 1944): of the
// events k = 0, 1, 2, … of one sequence, those where frac(offset + k·q) < q,
// with one offset uniform in [0, 1) for the whole sequence. Each event is
// selected with probability q, as by a coin of its own, so an estimate made
// at the selected events and weighed by 1/q is unbiased; but any n
// consecutive events hold ⌊n·q⌋ or ⌈n·q⌉ of them, so the count adds no
// variance that grows with the sequence's length (coins add n·q·(1 − q)).
// Formed in double: exact to 10⁻⁹ for k up to 10⁶.
bool systematic_selected(float offset, int k, float q);

}  // namespace jade
