#include "jade/core/parse.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace jade {

namespace {

// Comma-separated finite numbers; false when an item is not one.
bool parse_numbers(const std::string& text, std::vector<float>& v) {
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        try {
            std::size_t used = 0;
            v.push_back(std::stof(item, &used));
            if (used != item.size() || !std::isfinite(v.back())) return false;
        } catch (const std::exception&) {
            return false;
        }
    }
    return true;
}

}  // namespace

bool parse_vec3(const std::string& text, glm::vec3& out) {
    std::vector<float> v;
    if (!parse_numbers(text, v)) return false;
    glm::vec3 r;
    if (v.size() == 1) r = glm::vec3(v[0]);
    else if (v.size() == 3) r = glm::vec3(v[0], v[1], v[2]);
    else return false;
    if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z)) return false;
    out = r;
    return true;
}

bool parse_sphere(const std::string& text, glm::vec3& centre, float& radius) {
    std::vector<float> v;
    if (!parse_numbers(text, v) || v.size() != 4 || !(v[3] > 0.f)) return false;
    centre = glm::vec3(v[0], v[1], v[2]);
    radius = v[3];
    return true;
}

}  // namespace jade
