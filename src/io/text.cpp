#include "jade/io/text.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

namespace jade {

namespace OIIO = OIIO_NAMESPACE;

bool draw_text(RgbImage8& image, int x, int baseline_y, const std::string& text, int size,
               const Rgb8& colour) {
    if (image.width <= 0 || image.height <= 0 || text.empty()) return true;
    // The buffer wraps the image's own pixels: OIIO draws straight into them.
    OIIO::ImageBuf buf(OIIO::ImageSpec(image.width, image.height, 3, OIIO::TypeDesc::UINT8),
                       image.pixels.data());
    const float rgb[3] = {colour[0] / 255.0f, colour[1] / 255.0f, colour[2] / 255.0f};
    return OIIO::ImageBufAlgo::render_text(buf, x, baseline_y, text, size, "DejaVuSansMono", rgb);
}

}  // namespace jade
