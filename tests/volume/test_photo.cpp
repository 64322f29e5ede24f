// Photo input: formats, bit depths, alpha, mask, linear float, bad files.

#include "jade/core/error.h"
#include "jade/io/image_io.h"
#include "jade/core/display.h"
#include "jade/volume/photo.h"

#include "support/test_util.h"

#include <OpenImageIO/imageio.h>
#include <catch2/catch.hpp>

#include <fstream>

using namespace jade;
using jade_test::TempDir;
namespace OIIO = OIIO_NAMESPACE;

namespace {

template <typename T>
void write(const std::string& path, int w, int h, int ch, const std::vector<T>& px,
           OIIO::TypeDesc type) {
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    OIIO::ImageSpec spec(w, h, ch, type);
    if (ch == 4) {
        spec.alpha_channel = 3;
        spec.attribute("oiio:UnassociatedAlpha", 1);
    }
    REQUIRE(out->open(path, spec));
    REQUIRE(out->write_image(type, px.data()));
    REQUIRE(out->close());
}

}  // namespace

TEST_CASE("8-bit RGBA PNG: levels kept exactly, alpha >= 0.5 is foreground", "[photo]") {
    TempDir dir;
    // 2x2: opaque, alpha 128 (>= 0.5), alpha 127 (< 0.5), transparent.
    const std::vector<std::uint8_t> px = {10, 20, 30, 255, 40, 50, 60, 128,
                                          70, 80, 90, 127, 1, 2, 3, 0};
    write(dir.file("p.png"), 2, 2, 4, px, OIIO::TypeDesc::UINT8);
    const Photo p = load_photo(dir.file("p.png"));
    REQUIRE(p.width == 2);
    CHECK(p.levels[0] == Rgb8{10, 20, 30});
    // Half-transparent pixels keep their colour (no premultiplication).
    CHECK(p.levels[1] == Rgb8{40, 50, 60});
    CHECK(p.foreground == std::vector<std::uint8_t>{1, 1, 0, 0});
    CHECK(p.foreground_levels() == std::vector<Rgb8>{{10, 20, 30}, {40, 50, 60}});
}

TEST_CASE("16-bit PNG and TIFF map to the nearest 8-bit level", "[photo]") {
    TempDir dir;
    // 257 * 100 + 100 is 100.39 levels: rounds to 100. Alpha opaque.
    const std::vector<std::uint16_t> px = {0, 257 * 100 + 100, 65535, 65535};
    for (const char* name : {"p16.png", "p16.tif"}) {
        write(dir.file(name), 1, 1, 4, px, OIIO::TypeDesc::UINT16);
        const Photo p = load_photo(dir.file(name));
        CHECK(p.levels[0] == Rgb8{0, 100, 255});
        CHECK(p.foreground[0] == 1);
    }
}

TEST_CASE("float EXR is linear and is sRGB-encoded", "[photo]") {
    TempDir dir;
    const std::vector<float> px = {0.0f, 0.5f, 1.0f, 0.2f, 0.0031308f, 2.0f};
    write(dir.file("lin.exr"), 2, 1, 3, px, OIIO::TypeDesc::FLOAT);
    const Photo p = load_photo(dir.file("lin.exr"));
    // sRGB(0.5) = 0.7354 -> 187.5 -> 188; sRGB(0.2) = 0.4845 -> 123.6 -> 124;
    // the linear segment: 0.0031308 * 12.92 = 0.04045 -> 10; above 1 clamps.
    CHECK(p.levels[0] == Rgb8{0, 188, 255});
    CHECK(p.levels[1] == Rgb8{124, 10, 255});
    CHECK(srgb_decode(srgb_encode(0.3)) == Approx(0.3));
}

TEST_CASE("a gray image repeats its channel, and JPEG reads", "[photo]") {
    TempDir dir;
    const std::vector<std::uint8_t> gray = {0, 77, 200, 255};
    write(dir.file("g.png"), 2, 2, 1, gray, OIIO::TypeDesc::UINT8);
    CHECK(load_photo(dir.file("g.png")).levels[1] == Rgb8{77, 77, 77});
    std::vector<std::uint8_t> rgb(16 * 16 * 3, 128);
    write(dir.file("j.jpg"), 16, 16, 3, rgb, OIIO::TypeDesc::UINT8);
    const Photo j = load_photo(dir.file("j.jpg"));
    CHECK(j.foreground_count() == 256u);
    CHECK(std::abs(int(j.levels[0][0]) - 128) <= 2);  // lossy
}

TEST_CASE("a mask replaces the alpha, white is the object", "[photo]") {
    TempDir dir;
    const std::vector<std::uint8_t> px = {10, 10, 10, 20, 20, 20, 30, 30, 30, 40, 40, 40};
    write(dir.file("p.png"), 2, 2, 3, px, OIIO::TypeDesc::UINT8);
    write(dir.file("m.png"), 2, 2, 1, std::vector<std::uint8_t>{255, 0, 200, 100},
          OIIO::TypeDesc::UINT8);
    const Photo p = load_photo(dir.file("p.png"), dir.file("m.png"));
    CHECK(p.foreground == std::vector<std::uint8_t>{1, 0, 1, 0});
}

TEST_CASE("bad photos are one clear error naming the file", "[photo]") {
    TempDir dir;
    CHECK_THROWS_WITH(load_photo(dir.file("missing.png")),
                      Catch::Contains("missing.png") && Catch::Contains("no such file"));

    std::ofstream(dir.file("corrupt.png"), std::ios::binary) << "\x89PNG\r\n\x1a\nnot really";
    CHECK_THROWS_WITH(load_photo(dir.file("corrupt.png")), Catch::Contains("corrupt.png"));

    write(dir.file("clear.png"), 2, 1, 4, std::vector<std::uint8_t>{1, 2, 3, 0, 4, 5, 6, 10},
          OIIO::TypeDesc::UINT8);
    CHECK_THROWS_WITH(load_photo(dir.file("clear.png")),
                      Catch::Contains("clear.png") && Catch::Contains("no foreground"));

    write(dir.file("p.png"), 2, 2, 3, std::vector<std::uint8_t>(12, 9), OIIO::TypeDesc::UINT8);
    write(dir.file("m.png"), 3, 2, 1, std::vector<std::uint8_t>(6, 255), OIIO::TypeDesc::UINT8);
    CHECK_THROWS_WITH(load_photo(dir.file("p.png"), dir.file("m.png")),
                      Catch::Contains("m.png") && Catch::Contains("3x2") && Catch::Contains("2x2"));
    write(dir.file("black.png"), 2, 2, 1, std::vector<std::uint8_t>(4, 0), OIIO::TypeDesc::UINT8);
    CHECK_THROWS_AS(load_photo(dir.file("p.png"), dir.file("black.png")), Error);
}

TEST_CASE("images are written whole: no partial file after a failed write", "[photo]") {
    TempDir dir;
    CHECK_THROWS_AS(write_image_u8(dir.file("x.unknownext"), 1, 1, 3, {1, 2, 3}), Error);
    CHECK(dir.entries() == 0);
    write_image_u8(dir.file("ok.png"), 1, 1, 3, {1, 2, 3});
    CHECK(dir.entries() == 1);
    CHECK(load_photo(dir.file("ok.png")).levels[0] == Rgb8{1, 2, 3});
}
