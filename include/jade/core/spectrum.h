#pragma once
// RGB radiometric quantities. Transport is carried per RGB channel (docs/design.md, "Coefficients"):
// coefficients, throughputs and radiance are three floats, one per channel.

#include <glm/vec3.hpp>

#include <algorithm>

namespace jade {

using Spectrum = glm::vec3;

// The channels' names, for messages and reports.
inline const char* channel_name(int c) {
    static const char* const names[3] = {"red", "green", "blue"};
    return names[c];
}

inline float average(const Spectrum& s) { return (s.x + s.y + s.z) * (1.f / 3.f); }
inline float max_component(const Spectrum& s) { return std::max(s.x, std::max(s.y, s.z)); }
inline float min_component(const Spectrum& s) { return std::min(s.x, std::min(s.y, s.z)); }
inline bool is_finite(const Spectrum& s) {
    return s.x - s.x == 0.f && s.y - s.y == 0.f && s.z - s.z == 0.f;
}

}  // namespace jade
