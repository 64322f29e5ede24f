#pragma once
// Equal-area bins over the unit sphere: an n × n grid on the square of
// Clarberg's octahedral equal-area map (2008, "Fast equal-area mapping of
// the (hemi)sphere using SIMD"), which takes uniform points of [0, 1]² to
// uniform directions. So every bin holds 4π / n² steradians, a direction
// drawn uniformly in a bin's square is uniform over the bin, and a histogram
// of directions over the bins is a piecewise-constant density in solid
// angle (render/light_guide.h). Unlike bands in z, the bins keep their
// shape near the poles (a few degrees across everywhere for n = 24).

#include "jade/core/math.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace jade {

// The map from [0, 1]² to the unit sphere, and its inverse.
inline glm::vec3 equal_area_square_to_sphere(const glm::vec2& p) {
    const float u = 2.f * p.x - 1.f, v = 2.f * p.y - 1.f;
    const float up = std::abs(u), vp = std::abs(v);
    const float signed_distance = 1.f - (up + vp);  // > 0: the upper hemisphere
    const float r = 1.f - std::abs(signed_distance);
    const float phi = (r == 0.f ? 1.f : (vp - up) / r + 1.f) * (kPi / 4.f);
    const float z = std::copysign(1.f - r * r, signed_distance);
    const float s = r * std::sqrt(std::max(0.f, 2.f - r * r));
    return {std::copysign(std::cos(phi), u) * s, std::copysign(std::sin(phi), v) * s, z};
}

inline glm::vec2 equal_area_sphere_to_square(const glm::vec3& d) {
    const float x = std::abs(d.x), y = std::abs(d.y), z = std::min(std::abs(d.z), 1.f);
    const float r = std::sqrt(1.f - z);
    const float a = std::max(x, y), b = a == 0.f ? 0.f : std::min(x, y) / a;
    float phi = std::atan(b) * (2.f / kPi);
    if (x < y) phi = 1.f - phi;
    float v = phi * r, u = r - v;
    if (d.z < 0.f) {  // the lower hemisphere folds onto the square's corners
        std::swap(u, v);
        u = 1.f - u;
        v = 1.f - v;
    }
    return {0.5f * (std::copysign(u, d.x) + 1.f), 0.5f * (std::copysign(v, d.y) + 1.f)};
}

struct SphereBins {
    int n = 24;  // bins along each side of the square

    int count() const { return n * n; }
    float solid_angle() const { return 4.f * kPi / float(count()); }
    // The bin of unit direction w.
    int index(const glm::vec3& w) const {
        const glm::vec2 p = equal_area_sphere_to_square(w);
        const int i = std::clamp(int(p.x * float(n)), 0, n - 1), j = std::clamp(int(p.y * float(n)), 0, n - 1);
        return j * n + i;
    }
    // A direction uniform in solid angle over bin `bin`, from u1, u2 in [0, 1).
    glm::vec3 direction(int bin, float u1, float u2) const {
        const float i = float(bin % n), j = float(bin / n);
        return equal_area_square_to_sphere({(i + u1) / float(n), (j + u2) / float(n)});
    }
};

}  // namespace jade
