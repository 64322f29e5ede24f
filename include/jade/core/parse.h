#pragma once
// Parsing the small values flags and documents carry.

#include <glm/vec3.hpp>

#include <string>

namespace jade {

// "v" (all three components) or "x,y,z" → a finite vector; false when the
// text is neither.
bool parse_vec3(const std::string& text, glm::vec3& out);
// "x,y,z,r" → a sphere's centre and radius (finite, r > 0); false otherwise.
bool parse_sphere(const std::string& text, glm::vec3& centre, float& radius);

}  // namespace jade
