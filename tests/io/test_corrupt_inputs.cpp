// Every reader against damaged files: for each kind of input (PNG, JPEG,
// EXR, OBJ, GLB, a jaderender .vdb), a good file is cut short, has bytes
// flipped, and has its header's numbers overwritten, 120 to 300 times
// with a fixed seed. Each damaged file must be read or refused with a
// jade::Error (one line naming the file): no other exception, no crash, no
// hang (CTest's timeout), nothing allocated beyond what a header may ask.

#include "jade/core/error.h"
#include "jade/core/random.h"
#include "jade/geometry/mesh_io.h"
#include "jade/io/image_io.h"
#include "jade/io/vdb_io.h"
#include "jade/volume/material_volume.h"
#include "jade/volume/photo.h"

#include "support/test_util.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <functional>
#include <iterator>
#include <string>

using namespace jade;
using jade_test::TempDir;

namespace {

std::string bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// The k-th damaged copy of `good`: cut short, bytes flipped, or numbers in
// its first 256 bytes (where formats keep their sizes and offsets) overwritten.
std::string damaged(const std::string& good, int k, SampleStream& rng) {
    std::string d = good;
    const auto at = [&](std::size_t limit) { return std::size_t(rng.uniform() * float(limit)) % limit; };
    switch (k % 3) {
    case 0:  // cut short
        d.resize(at(good.size()));
        break;
    case 1:  // 1 to 8 bytes flipped
        for (int i = 0, n = 1 + int(at(8)); i < n; ++i) d[at(d.size())] ^= char(1 + at(255));
        break;
    default: {  // a 32-bit number of the header made huge, zero or negative
        const std::size_t head = std::min<std::size_t>(256, d.size());
        if (head < 4) break;
        const std::size_t p = at(head - 3);
        const std::uint32_t values[] = {0xffffffffu, 0x7fffffffu, 0u, 0x00ea6000u, 0x80000000u};
        const std::uint32_t v = values[at(5)];
        for (int b = 0; b < 4; ++b) d[p + std::size_t(b)] = char((v >> (8 * b)) & 0xff);
        break;
    }
    }
    return d;
}

// Runs `read` on `copies` damaged copies of the file at `good_path`.
void fuzz(const std::string& name, const std::string& good_path, int copies,
          const std::function<void(const std::string&)>& read) {
    TempDir dir;
    const std::string good = bytes_of(good_path);
    REQUIRE(!good.empty());
    REQUIRE_NOTHROW(read(good_path));  // the good file reads
    const std::string ext = good_path.substr(good_path.rfind('.'));
    // Seeded by the file's name alone (not its temporary folder), so every
    // run damages the same bytes.
    SampleStream rng(2026, std::hash<std::string>{}(name.substr(name.rfind('/') + 1)), 0);
    int refused = 0;
    for (int k = 0; k < copies; ++k) {
        const std::string path = dir.file("damaged" + std::to_string(k) + ext);
        std::ofstream(path, std::ios::binary) << damaged(good, k, rng);
        INFO(name << " copy " << k << " (" << (k % 3 == 0 ? "cut" : k % 3 == 1 ? "flipped" : "header") << ")");
        try {
            read(path);
        } catch (const Error& e) {
            ++refused;
            const std::string what = e.what();
            CHECK(what.find('\n') == std::string::npos);
            CHECK(what.find(path) != std::string::npos);
        } catch (const std::exception& e) {
            FAIL("not a jade::Error: " << e.what());
        }
        std::remove(path.c_str());
    }
    INFO(name << ": " << refused << " of " << copies << " refused");
    CHECK(refused > 0);
}

}  // namespace

TEST_CASE("damaged images: read whole or refused in one line", "[corrupt]") {
    TempDir dir;
    std::vector<std::uint8_t> px(24 * 16 * 4);
    for (std::size_t i = 0; i < px.size(); ++i) px[i] = std::uint8_t(i * 7);
    write_image_u8(dir.file("good.png"), 24, 16, 4, px);
    std::vector<float> hdr(24 * 16 * 3);
    for (std::size_t i = 0; i < hdr.size(); ++i) hdr[i] = float(i % 17) * 0.25f;
    write_image_f32(dir.file("good.exr"), 24, 16, 3, hdr);
    const std::string jpeg = JADE_DATA_DIR "/photos/ambientcg_Onyx002_512_diff.jpg";
    for (const std::string& f : {dir.file("good.png"), jpeg, dir.file("good.exr")}) {
        fuzz("photo " + f, f, 150, [](const std::string& p) { load_photo(p); });
        fuzz("image " + f, f, 150, [](const std::string& p) { read_image_f32(p); });
    }
}

TEST_CASE("damaged meshes: read whole or refused in one line", "[corrupt]") {
    TempDir dir;
    std::ofstream(dir.file("cube.obj")) << "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\n"
                                           "v 1 1 1\nv -1 1 1\nf 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\n"
                                           "f 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    fuzz("obj", dir.file("cube.obj"), 300, [](const std::string& p) { load_mesh(p); });
    fuzz("glb", JADE_DATA_DIR "/meshes/greek-vase-01.glb", 300, [](const std::string& p) { load_mesh(p); });
}

TEST_CASE("damaged .vdb volumes: read whole or refused in one line", "[corrupt]") {
    TempDir dir;
    NoiseParams noise;
    noise.resolution = 12;
    Photo photo;
    photo.path = "stone.png";
    photo.width = photo.height = 8;
    for (int i = 0; i < 64; ++i) {
        photo.levels.push_back({std::uint8_t(i * 4), std::uint8_t(200 - i), std::uint8_t(i * 3)});
        photo.foreground.push_back(1);
    }
    MaterialVolume v = build_material_volume(photo, noise, MatchMode::Joint, OpticalParams{});
    v.cube.min = {-0.5, -0.5, -0.5};
    v.cube.side = 1.0;
    write_material_vdb(dir.file("good.vdb"), v);
    // 120 copies, not 300: each read starts jaderender-vdb-check once or
    // twice, and a start costs 60–75 ms, mostly resolving libopenvdb's symbols
    // (the other readers run in this process).
    fuzz("vdb", dir.file("good.vdb"), 120, [](const std::string& p) { read_material_vdb(p); });
}
