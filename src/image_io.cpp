#include "jade/image_io.h"

#include "jade/atomic_file.h"
#include "jade/error.h"

#include <OpenImageIO/imageio.h>

namespace jade {

namespace OIIO = OIIO_NAMESPACE;

namespace {
template <typename T>
void write_image(const std::string& path, int width, int height, int channels,
                 const std::vector<T>& pixels, OIIO::TypeDesc type) {
    if (pixels.size() != std::size_t(width) * height * channels)
        throw Error("internal: image buffer size does not match its dimensions for " + path);
    AtomicFile file(path);
    auto out = OIIO::ImageOutput::create(path);
    if (!out) fail_file(path, "no image writer for this file extension");
    OIIO::ImageSpec spec(width, height, channels, type);
    if (channels == 4) {
        spec.alpha_channel = 3;
        // Our pixels are straight (unassociated) colour beside their coverage.
        spec.attribute("oiio:UnassociatedAlpha", 1);
    }
    if (type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", "zip");
    if (!out->open(file.temp_path(), spec) || !out->write_image(type, pixels.data()) ||
        !out->close())
        fail_file(path, "cannot write image: " + out->geterror());
    file.commit();
}
}  // namespace

void write_image_u8(const std::string& path, int width, int height, int channels,
                    const std::vector<std::uint8_t>& pixels) {
    write_image(path, width, height, channels, pixels, OIIO::TypeDesc::UINT8);
}

void write_image_f32(const std::string& path, int width, int height, int channels,
                     const std::vector<float>& pixels) {
    write_image(path, width, height, channels, pixels, OIIO::TypeDesc::FLOAT);
}

}  // namespace jade
