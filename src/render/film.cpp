#include "jade/render/film.h"

#include "jade/core/error.h"
#include "jade/core/display.h"

#include <algorithm>

#include <cmath>
#include <limits>

namespace jade {

namespace {
// Rousselle, Knaus & Zwicker 2011's guard against division by near-black pixels.
constexpr double kRelativeEpsilon = 0.01;
}

Film::Film(int width, int height)
    : width_(width), height_(height), sum_(std::size_t(width) * height * 3, 0.0),
      sum_sq_(std::size_t(width) * height * 3, 0.0), hits_(std::size_t(width) * height, 0) {}

void Film::add_sample(int x, int y, const Spectrum& radiance, bool hit_object) {
    const std::size_t i = std::size_t(y) * width_ + x;
    for (int c = 0; c < 3; ++c) {
        const double v = radiance[c];
        sum_[3 * i + c] += v;
        sum_sq_[3 * i + c] += v * v;
    }
    hits_[i] += hit_object ? 1u : 0u;
}

Spectrum Film::mean(int x, int y) const {
    if (spp_ == 0) return Spectrum(0.f);
    const std::size_t i = std::size_t(y) * width_ + x;
    return Spectrum(float(sum_[3 * i] / spp_), float(sum_[3 * i + 1] / spp_),
                    float(sum_[3 * i + 2] / spp_));
}

Spectrum Film::variance_of_mean(int x, int y) const {
    if (spp_ < 2) return Spectrum(std::numeric_limits<float>::quiet_NaN());
    const std::size_t i = std::size_t(y) * width_ + x;
    Spectrum v;
    const double n = spp_;
    for (int c = 0; c < 3; ++c) {
        const double m = sum_[3 * i + c] / n;
        const double var = std::max(0.0, (sum_sq_[3 * i + c] - n * m * m) / (n - 1.0));
        v[c] = float(var / n);
    }
    return v;
}

float Film::coverage(int x, int y) const {
    if (spp_ == 0) return 0.f;
    return float(hits_[std::size_t(y) * width_ + x]) / float(spp_);
}

double Film::estimated_relative_error() const {
    if (spp_ < 2) return std::numeric_limits<double>::quiet_NaN();
    const double n = spp_;
    // The object's mean value sets the scale of the regulariser, so that the
    // measure does not depend on the image's exposure.
    double level = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < hits_.size(); ++i) {
        if (hits_[i] == 0) continue;
        for (int c = 0; c < 3; ++c) level += sum_[3 * i + c] / n;
        count += 3;
    }
    if (count == 0) return std::numeric_limits<double>::quiet_NaN();
    level /= double(count);
    const double epsilon = kRelativeEpsilon * std::max(level * level, 1e-30);
    double sum = 0.0;
    for (std::size_t i = 0; i < hits_.size(); ++i) {
        if (hits_[i] == 0) continue;
        for (int c = 0; c < 3; ++c) {
            const double m = sum_[3 * i + c] / n;
            const double var = std::max(0.0, (sum_sq_[3 * i + c] - n * m * m) / (n - 1.0)) / n;
            sum += var / (m * m + epsilon);
        }
    }
    return std::sqrt(sum / double(count));
}

std::vector<float> Film::rgba(bool alpha_is_coverage) const {
    std::vector<float> out(std::size_t(width_) * height_ * 4);
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const std::size_t i = std::size_t(y) * width_ + x;
            const Spectrum m = mean(x, y);
            out[4 * i] = m.x;
            out[4 * i + 1] = m.y;
            out[4 * i + 2] = m.z;
            out[4 * i + 3] = alpha_is_coverage ? coverage(x, y) : 1.f;
        }
    return out;
}

ReferenceError compare_with_reference(const Film& film, const ImageF32& ref) {
    if (ref.width != film.width() || ref.height != film.height() || ref.channels < 3)
        throw Error("the reference image is " + std::to_string(ref.width) + "x" +
                    std::to_string(ref.height) + " with " + std::to_string(ref.channels) +
                    " channels; the render is " + std::to_string(film.width()) + "x" +
                    std::to_string(film.height()) + " RGB");
    double se = 0.0, rel = 0.0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const Spectrum m = film.mean(x, y);
            for (int c = 0; c < 3; ++c) {
                const double r = ref.at(x, y, c), e = double(m[c]) - r;
                se += e * e;
                rel += e * e / (r * r + kRelativeEpsilon);
            }
        }
    const double n = 3.0 * film.width() * film.height();
    return {std::sqrt(se / n), rel / n};
}

}  // namespace jade

namespace jade {

void write_film(const Film& film, const std::string& exr_path, const std::string& png_path,
                bool alpha_is_coverage, float png_exposure) {
    const std::vector<float> rgba = film.rgba(alpha_is_coverage);
    std::vector<std::uint8_t> png;
    if (!png_path.empty()) {
        png.resize(rgba.size());
        for (std::size_t i = 0; i < rgba.size(); i += 4) {
            const float a = rgba[i + 3];
            for (int c = 0; c < 3; ++c) {
                // With coverage alpha the film holds colour × coverage; PNG wants it straight.
                const float straight =
                    png_exposure * (alpha_is_coverage && a > 0.f ? rgba[i + c] / a : rgba[i + c]);
                png[i + c] = display_level(straight);
            }
            png[i + 3] = std::uint8_t(std::lround(255.f * std::clamp(a, 0.f, 1.f)));
        }
    }
    write_image_f32(exr_path, film.width(), film.height(), 4, rgba, /*associated_alpha=*/true);
    if (!png_path.empty()) write_image_u8(png_path, film.width(), film.height(), 4, png);
}

}  // namespace jade
