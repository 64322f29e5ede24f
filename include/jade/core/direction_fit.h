#pragma once
// Directions that change with position over a small region (a cell of the
// light guide, render/light_guide.h): the weighted least-squares fit of an
// affine model w ≈ a + J·x to unit directions w seen at positions x, and
// the spread of the directions about the model, as an elliptic cone at any
// x (core/sampling.h). Light refracted in through a curved surface changes
// its direction across a cell by as much as a small disc's own width; the
// model follows that change to first order, so the cone at x covers the
// directions that arrive at x rather than the union over the cell.
//
// The sums are 28 plain numbers, so that the guide can add them from many
// threads in fixed point, whose integer sums do not depend on their order.

#include "jade/core/sampling.h"

#include <glm/vec3.hpp>

#include <array>
#include <optional>

namespace jade {

// The weights q_i and positions x_i of one stretch's samples, summed: Σq,
// Σq·x and Σq·x xᵀ (its upper triangle, row by row).
struct StretchSums {
    double q = 0.0;
    glm::dvec3 qx{0.0};
    std::array<double, 6> qxx{};
    void add(double weight, const glm::dvec3& x);
};

// What a fit needs from every stretch, each of one direction w:
// Σq, Σq·x (3), Σq·x xᵀ (6), Σq·w (3), Σq·w xᵀ (9, row by row), Σq·w wᵀ (6).
struct DirectionSums {
    static constexpr int kCount = 28;
    std::array<double, kCount> v{};
    void add(const StretchSums& s, const glm::vec3& w);
};

// The fitted model and the cone about it.
struct DirectionLobe {
    std::array<std::array<float, 4>, 3> model{};  // w's components from (1, x, y, z)
    glm::vec3 major{1.f, 0.f, 0.f};  // the spread's widest direction (at x = 0)
    float r_major = 0.f, r_minor = 0.f;
    // The cone at x: axis the model's direction there, its section the
    // ellipse of the spread; none where the model's direction vanishes.
    std::optional<EllipticCone> cone(const glm::vec3& x) const;
};

struct DirectionFitSettings {
    // Added to the positions' second moments, times Σq: pulls a fit from
    // few or collinear positions toward a constant direction.
    double ridge = 0.01;
    // The cone's radii over those of a uniform ellipse with the residuals'
    // spread (2σ along each principal axis): room for the model's error.
    double margin = 1.5;
    // No lobe when the spread needs a radius above this on the tangent
    // plane (directions from several faces, or none in particular).
    double widest = 0.6;
};

// The lobe of the sums, or none: no weight, a vanishing mean direction, or
// a spread wider than settings.widest.
std::optional<DirectionLobe> fit_direction_lobe(const DirectionSums& sums, const DirectionFitSettings& settings = {});

}  // namespace jade
