#include "jade/io/image_io.h"

#include "jade/io/atomic_file.h"
#include "jade/core/display.h"
#include "jade/core/error.h"
#include "jade/core/quiet_stderr.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

namespace jade {

namespace OIIO = OIIO_NAMESPACE;

namespace {
template <typename T>
void write_image(const std::string& path, int width, int height, int channels,
                 const std::vector<T>& pixels, OIIO::TypeDesc type, bool associated) {
    if (pixels.size() != std::size_t(width) * height * channels)
        throw Error("internal: image buffer size does not match its dimensions for " + path);
    AtomicFile file(path);
    auto out = OIIO::ImageOutput::create(path);
    if (!out) fail_file(path, "no image writer for this file extension");
    OIIO::ImageSpec spec(width, height, channels, type);
    if (channels == 4) {
        spec.alpha_channel = 3;
        // Straight colour beside its coverage must be marked, or OIIO would
        // divide it by alpha once more when writing PNG.
        if (!associated) spec.attribute("oiio:UnassociatedAlpha", 1);
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
    write_image(path, width, height, channels, pixels, OIIO::TypeDesc::UINT8, false);
}

void write_image_f32(const std::string& path, int width, int height, int channels,
                     const std::vector<float>& pixels, bool associated_alpha) {
    write_image(path, width, height, channels, pixels, OIIO::TypeDesc::FLOAT, associated_alpha);
}


namespace {
ImageF32 read_image(const std::string& path);
}

// A damaged header can make a decoder allocate whatever it claims: that is
// the file's fault, said in one line, like any other damage.
ImageF32 read_image_f32(const std::string& path) {
    try {
        return read_image(path);
    } catch (const std::bad_alloc&) {
        fail_file(path, "damaged: its header asks for more memory than an image of its size needs");
    }
}

namespace {
ImageF32 read_image(const std::string& path) {
    const QuietStderr quiet;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        const std::string why = OIIO::geterror();
        fail_file(path, why.empty() ? "cannot open as an image" : "cannot read as an image: " + why);
    }
    const OIIO::ImageSpec& spec = in->spec();
    ImageF32 img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = std::min(spec.nchannels, kMaxImageChannels);  // RGBA; further channels are not ours
    if (img.width < 1 || img.height < 1 || img.channels < 1) fail_file(path, "image has no pixels");
    // The header's size is checked before anything is allocated for it.
    if (std::int64_t(img.width) * img.height > kMaxImagePixels)
        fail_file(path, "the image is " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                            " pixels, more than the " + std::to_string(kMaxImagePixels / 1000000) +
                            " million read here");
    img.pixels.resize(std::size_t(img.width) * img.height * img.channels);
    // A decoder may fill what it could not read (a truncated JPEG decodes as
    // grey below the cut) and report it only as a message: any message is a failure.
    const bool read = in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data());
    const std::string message = in->geterror();
    if (!read || !message.empty())
        fail_file(path, "cannot decode" + (message.empty() ? std::string() : ": " + message));
    const bool linear = spec.format.is_floating_point();
    const std::string space = spec.get_string_attribute("oiio:ColorSpace");
    if (!linear && space != "Linear" && space != "linear") {
        // 8/16-bit images are display-encoded: back to linear radiance.
        for (std::size_t i = 0; i < img.pixels.size(); ++i) {
            if (int(i % img.channels) == spec.alpha_channel) continue;
            img.pixels[i] = float(srgb_decode(img.pixels[i]));
        }
    }
    for (float v : img.pixels)
        if (!std::isfinite(v)) fail_file(path, "image holds NaN or infinite values");
    return img;
}
}  // namespace

ImageF32 resize_image(const ImageF32& image, int width, int height) {
    const OIIO::ImageSpec in_spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
    const OIIO::ImageBuf src(in_spec, const_cast<float*>(image.pixels.data()));
    OIIO::ImageBuf dst(OIIO::ImageSpec(width, height, image.channels, OIIO::TypeDesc::FLOAT));
    if (!OIIO::ImageBufAlgo::resize(dst, src)) throw Error("cannot resize an image: " + dst.geterror());
    ImageF32 out{width, height, image.channels, std::vector<float>(std::size_t(width) * height * image.channels)};
    dst.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, out.pixels.data());
    return out;
}

}  // namespace jade
