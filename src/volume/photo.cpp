#include "jade/volume/photo.h"

#include "jade/core/display.h"
#include "jade/core/error.h"
#include "jade/core/quiet_stderr.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace jade {

namespace OIIO = OIIO_NAMESPACE;

std::array<int, 4> Photo::foreground_box() const {
    int x0 = width, x1 = -1, y0 = height, y1 = -1;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            if (foreground[std::size_t(y) * width + x]) {
                x0 = std::min(x0, x), x1 = std::max(x1, x);
                y0 = std::min(y0, y), y1 = std::max(y1, y);
            }
    if (x1 < 0) return {0, 0, width, height};
    return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

std::size_t Photo::foreground_count() const {
    return std::size_t(std::count(foreground.begin(), foreground.end(), std::uint8_t(1)));
}

std::vector<Rgb8> Photo::foreground_levels() const {
    std::vector<Rgb8> out;
    out.reserve(foreground_count());
    for (std::size_t i = 0; i < levels.size(); ++i)
        if (foreground[i]) out.push_back(levels[i]);
    return out;
}

namespace {

struct RawImage {
    int width = 0, height = 0, channels = 0;
    int alpha_channel = -1;
    bool linear = false;  // float data: linear light, to be sRGB-encoded
    std::vector<float> pixels;
};

RawImage read_raw(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail_file(path, "no such file");
    // Keep PNG alpha unassociated: a half-transparent edge pixel must keep its
    // colour, not be darkened by premultiplication.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    QuietStderr quiet;
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) {
        const std::string why = OIIO::geterror();
        fail_file(path, "cannot read as an image (" + (why.empty() ? "unknown format" : why) + ")");
    }
    const OIIO::ImageSpec& spec = in->spec();
    RawImage img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = std::min(spec.nchannels, kMaxImageChannels);
    img.alpha_channel = spec.alpha_channel < img.channels ? spec.alpha_channel : -1;
    if (img.alpha_channel < 0 && (img.channels == 2 || img.channels == 4))
        img.alpha_channel = img.channels - 1;  // gray+alpha or RGBA without the tag
    img.linear = spec.format.is_floating_point();
    if (img.width <= 0 || img.height <= 0 || img.channels <= 0)
        fail_file(path, "the image is empty");
    // The header's size is checked before anything is allocated for it.
    if (std::int64_t(img.width) * img.height > kMaxImagePixels)
        fail_file(path, "the photo is " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                            " pixels, more than the " + std::to_string(kMaxImagePixels / 1000000) +
                            " million read here");
    img.pixels.resize(std::size_t(img.width) * img.height * img.channels);
    // A decoder may fill what it could not read (a truncated JPEG decodes as
    // grey below the cut) and report it only as a message: any message is a
    // failure, so a photo is never half-read.
    const bool read = in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data());
    const std::string why = in->geterror();
    if (!read || !why.empty())
        fail_file(path, "the image data is corrupt or truncated" + (why.empty() ? std::string() : " (" + why + ")"));
    for (float v : img.pixels)
        if (!std::isfinite(v)) fail_file(path, "the image contains NaN or infinite values");
    return img;
}

std::uint8_t to_level(float v, bool linear) {
    return linear ? display_level(v) : level_of_encoded(v);
}

}  // namespace

void validate_photo_span(double span, const char* name) {
    if (!(span >= kMinPhotoSpan && span <= kMaxPhotoSpan)) {
        char text[200];
        std::snprintf(text, sizeof text, "%s must be between %g and %g cube sides, got %g", name, kMinPhotoSpan,
                      kMaxPhotoSpan, span);
        throw Error(text);
    }
}

std::string photo_span_note(double span) {
    if (span == 1.0) return "";
    char text[48];
    std::snprintf(text, sizeof text, " (spanning %g cube sides)", span);
    return text;
}

Photo load_photo(const std::string& path, const std::string& mask_path, double span) {
    validate_photo_span(span);
    const RawImage img = read_raw(path);
    Photo photo;
    photo.path = path;
    photo.span = span;
    photo.width = img.width;
    photo.height = img.height;
    const std::size_t n = std::size_t(img.width) * img.height;
    photo.levels.resize(n);
    photo.foreground.assign(n, 1);

    // Colour channels: the first three that are not alpha; gray images repeat
    // their single channel.
    std::vector<int> colour;
    for (int c = 0; c < img.channels && colour.size() < 3; ++c)
        if (c != img.alpha_channel) colour.push_back(c);
    while (colour.size() < 3) colour.push_back(colour.back());

    for (std::size_t i = 0; i < n; ++i) {
        const float* p = &img.pixels[i * img.channels];
        for (int c = 0; c < 3; ++c) photo.levels[i][c] = to_level(p[colour[c]], img.linear);
        if (img.alpha_channel >= 0) photo.foreground[i] = p[img.alpha_channel] >= 0.5f;
    }

    if (!mask_path.empty()) {
        const RawImage mask = read_raw(mask_path);
        if (mask.width != img.width || mask.height != img.height)
            fail_file(mask_path, "the mask is " + std::to_string(mask.width) + "x" +
                                     std::to_string(mask.height) + " but the photo is " +
                                     std::to_string(img.width) + "x" +
                                     std::to_string(img.height));
        for (std::size_t i = 0; i < n; ++i)
            photo.foreground[i] = mask.pixels[i * mask.channels] >= 0.5f;
        if (photo.foreground_count() == 0)
            fail_file(mask_path, "the mask has no white (object) pixel");
    }
    if (photo.foreground_count() == 0)
        fail_file(path, "no foreground pixel: every pixel has alpha below 0.5");
    return photo;
}

}  // namespace jade
