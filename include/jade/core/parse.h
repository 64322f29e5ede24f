#pragma once
// Parsing the small values flags and documents carry.

#include <glm/vec3.hpp>

#include <string>

namespace jade {

// "v" (all three components) or "x,y,z" → a finite vector; false when the
// text is neither.
bool parse_vec3(const std::string& text, glm::vec3& out);

}  // namespace jade
