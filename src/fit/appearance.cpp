#include "jade/fit/appearance.h"

#include "jade/core/math.h"
#include "jade/volume/structure_estimate.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace jade {

double render_pixels_per_side(const CameraParams& camera, const Cube& cube) {
    const glm::dvec3 centre(cube.min[0] + 0.5 * cube.side, cube.min[1] + 0.5 * cube.side,
                            cube.min[2] + 0.5 * cube.side);
    const double distance = glm::length(glm::dvec3(camera.origin) - centre);
    const double footprint = 2.0 * distance * std::tan(radians(0.5 * double(camera.fov_degrees))) / camera.width;
    return cube.side / footprint;
}

TextureSpectrum photo_spectrum(const Photo& photo) {
    return texture_spectrum(photo_luma(photo), photo_pixels_per_side(photo));
}

Appearance compare_appearance(const RgbHistogram& photo_histogram, const TextureSpectrum& photo,
                              const DisplayStatistics& render, double pixels_per_side) {
    Appearance a;
    for (int c = 0; c < 3; ++c) {
        a.a_photo[c] = photo_histogram.mean(c);
        a.a_render[c] = render.a[c];
        a.s_photo[c] = photo_histogram.spread(c);
        a.s_render[c] = render.s[c];
        a.d[c] = histogram_distance(render.histogram, photo_histogram, c);
    }
    a.photo = photo;
    a.render = texture_spectrum(render.luma, pixels_per_side, render.luma_noise_variance);
    a.structure = structure_distance(a.render, a.photo);
    return a;
}

}  // namespace jade
