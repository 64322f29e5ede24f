#include "jade/render/medium.h"

namespace jade {

MajorantSegment Medium::majorant_segment(const glm::vec3&, const glm::vec3&, float t_min,
                                         float t_max) const {
    return {t_min, t_max, majorant()};
}

}  // namespace jade
