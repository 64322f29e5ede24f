// The .vdb file: exact round trip, and what plain OpenVDB sees in it.

#include "jade/core/error.h"
#include "jade/volume/material_volume.h"
#include "jade/geometry/mesh.h"
#include "jade/io/vdb_io.h"

#include "support/test_util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <set>
#include <cmath>
#include <openvdb/openvdb.h>

#include <fstream>

using namespace jade;
using jade_test::TempDir;

namespace {

Photo sample_photo() {
    Photo photo;
    photo.path = "stone.png";
    photo.width = 32;
    photo.height = 32;
    for (int i = 0; i < 1024; ++i) {
        photo.levels.push_back(
            {std::uint8_t(i % 256), std::uint8_t((i * 7) % 256), std::uint8_t(255 - i % 256)});
        photo.foreground.push_back(1);
    }
    return photo;
}

MaterialVolume sample_volume(int s, OpticalParams optics, NoiseParams n = {}) {
    n.resolution = s;
    n.seed = 11;
    MaterialVolume v = build_material_volume(sample_photo(), n, MatchMode::Joint, optics);
    v.cube.min = {-1.0, 0.5, 2.0};
    v.cube.side = 3.0;
    return v;
}

// Every grid and the file's metadata, as plain OpenVDB reads them.
std::pair<openvdb::GridPtrVecPtr, openvdb::MetaMap::Ptr> read_all(const std::string& path) {
    openvdb::initialize();
    openvdb::io::File f(path);
    f.open();
    auto grids = f.getGrids();
    auto meta = f.getMetadata();
    f.close();
    return {grids, meta};
}

void require_same(const MaterialVolume& a, const MaterialVolume& b) {
    REQUIRE(a.resolution == b.resolution);
    CHECK(a.levels == b.levels);
    CHECK(a.noise.octave_count() == b.noise.octave_count());
    CHECK(a.noise.k == b.noise.k);
    CHECK(a.noise.seed == b.noise.seed);
    CHECK(a.noise.frequency == b.noise.frequency);
    CHECK(a.noise.stretch == b.noise.stretch);
    CHECK(a.noise.angle == b.noise.angle);
    CHECK(a.noise.bands == b.noise.bands);
    CHECK(a.noise.warp == b.noise.warp);
    CHECK(a.noise.fold == b.noise.fold);
    CHECK(a.noise.veins == b.noise.veins);
    CHECK(a.noise.sharpen == b.noise.sharpen);
    CHECK(a.noise.sharpen_radius == b.noise.sharpen_radius);
    CHECK(a.noise.vein_frequency == b.noise.vein_frequency);
    CHECK(a.noise.vein_width == b.noise.vein_width);
    CHECK(a.noise.layers == b.noise.layers);
    CHECK(a.noise.exemplar == b.noise.exemplar);
    CHECK(a.noise.exemplar_wander == b.noise.exemplar_wander);
    CHECK(a.structure == b.structure);
    CHECK(a.match == b.match);
    CHECK(a.optics.extinction == b.optics.extinction);
    CHECK(a.optics.ds == b.optics.ds);
    CHECK(a.optics.da == b.optics.da);
    CHECK(a.optics.ks == b.optics.ks);
    CHECK(a.optics.density_scale == b.optics.density_scale);
    CHECK(a.optics.contrast == b.optics.contrast);
    CHECK(a.optics.mean_level == b.optics.mean_level);
    CHECK(a.cube.min == b.cube.min);
    CHECK(a.cube.side == b.cube.side);
    CHECK(a.photo == b.photo);
    CHECK(a.photo_span == b.photo_span);
}

}  // namespace

TEST_CASE("write -> read round trip is exact", "[vdb]") {
    TempDir dir;
    OpticalParams defaults;
    OpticalParams fitted;
    fitted.ks = {0.3, -0.2, 0.05};  // a negative k_s clamps some sigma_s at 0
    fitted.da = 0.25;
    OpticalParams no_absorption;  // levels must then come from sigma_s
    no_absorption.da = 0.0;
    no_absorption.ks = {0.1, 0.0, 2.0};
    // Coefficients beyond half precision's range (up to 3.3e5 > 65504 on this
    // 3-wide cube; down to 1e-6, below its normal range): full floats.
    OpticalParams dense, thin;
    dense.density_scale = 1e6;
    thin.density_scale = 1e-3;
    OpticalParams paper = fitted;  // §5.1's extinction
    paper.extinction = Extinction::Paper;
    for (const OpticalParams& optics : {defaults, fitted, no_absorption, dense, thin, paper}) {
        // 20 is not a multiple of the 8-voxel leaf: partial leaves too.
        const MaterialVolume v = sample_volume(20, optics);
        write_material_vdb(dir.file("v.vdb"), v);
        require_same(v, read_material_vdb(dir.file("v.vdb")));
    }
}

TEST_CASE("every resolution reads back: slabs clipped by world bounds keep their edge voxels", "[vdb]") {
    // 12³ could not be read back: the slab's clipping box, put exactly on the
    // voxel centres, lost the last row to rounding at h = 1/12 on a unit cube.
    TempDir dir;
    for (int s : {2, 3, 5, 7, 11, 12, 13, 24, 33, 40}) {
        INFO("resolution " << s);
        MaterialVolume v = sample_volume(s, OpticalParams{});
        v.cube.min = {-0.5, -0.5, -0.5};
        v.cube.side = 1.0;
        write_material_vdb(dir.file("v.vdb"), v);
        require_same(v, read_material_vdb(dir.file("v.vdb")));
    }
}

TEST_CASE("a file rewritten by another tool still reads: integers as Int32 or Int64, the photo's file name only",
          "[vdb]") {
    // pyopenvdb stores every Python int as Int32; OpenVDB's own tools keep
    // Int64. The file that comes back must read the same either way, and it
    // names its photo without the path of the machine that made it.
    TempDir dir;
    MaterialVolume v = sample_volume(12, OpticalParams{});
    v.photo = "/home/someone/stones/onyx.png";
    v.noise.seed = 3000000000u;  // above Int32's range: its bits must survive
    write_material_vdb(dir.file("v.vdb"), v);
    openvdb::io::File in(dir.file("v.vdb"));
    in.open(false);
    const openvdb::GridPtrVec grids = *in.getGrids();
    openvdb::MetaMap::Ptr meta = in.getMetadata();
    in.close();
    CHECK(meta->metaValue<std::string>("jade:photo") == "onyx.png");
    meta->removeMeta("jade:seed");
    meta->insertMeta("jade:seed", openvdb::Int32Metadata(std::int32_t(v.noise.seed)));
    meta->removeMeta("jade:resolution");
    meta->insertMeta("jade:resolution", openvdb::Int64Metadata(12));
    openvdb::io::File out(dir.file("rewritten.vdb"));
    out.write(grids, *meta);
    out.close();
    const MaterialVolume back = read_material_vdb(dir.file("rewritten.vdb"));
    CHECK(back.noise.seed == v.noise.seed);
    CHECK(back.resolution == 12);
    CHECK(back.levels == v.levels);
    CHECK(back.photo == "onyx.png");
}

TEST_CASE("a file cut short or damaged is refused, wherever it is cut", "[vdb]") {
    // OpenVDB reads some truncated files without complaint; the grids the
    // levels come from are written last and checked against a digest.
    TempDir dir;
    OpticalParams optics;
    const MaterialVolume v = sample_volume(24, optics);
    write_material_vdb(dir.file("v.vdb"), v);
    std::string bytes;
    {
        std::ifstream in(dir.file("v.vdb"), std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    for (std::size_t cut : {std::size_t(1), std::size_t(40), std::size_t(300), std::size_t(5000), bytes.size() / 2}) {
        INFO("cut by " << cut << " of " << bytes.size() << " bytes");
        std::ofstream(dir.file("cut.vdb"), std::ios::binary) << bytes.substr(0, bytes.size() - cut);
        CHECK_THROWS_AS(read_material_vdb(dir.file("cut.vdb")), Error);
    }
    // One byte flipped in the last grid's data.
    std::string flipped = bytes;
    flipped[flipped.size() - 100] = char(flipped[flipped.size() - 100] ^ 0x5a);
    std::ofstream(dir.file("flipped.vdb"), std::ios::binary) << flipped;
    CHECK_THROWS_AS(read_material_vdb(dir.file("flipped.vdb")), Error);
}

TEST_CASE("a header that asks for gigabytes is refused by the checking process, not allocated here", "[vdb]") {
    // OpenVDB reads a grid's type name by the length written before it; made
    // 1.44 GB, it would allocate that much before failing. The check reads
    // the header in jaderender-vdb-check under a 512 MB budget
    // (jade/io/vdb_check.h), and the refusal names the file in one line.
    TempDir dir;
    write_material_vdb(dir.file("v.vdb"), sample_volume(8, OpticalParams{}));
    std::string bytes;
    {
        std::ifstream in(dir.file("v.vdb"), std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::size_t type = bytes.find("Tree_");
    REQUIRE(type != std::string::npos);
    REQUIRE(type >= 4);
    const std::uint32_t huge = 0x56000000u;
    for (int b = 0; b < 4; ++b) bytes[type - 4 + std::size_t(b)] = char((huge >> (8 * b)) & 0xff);
    std::ofstream(dir.file("huge.vdb"), std::ios::binary) << bytes;
    try {
        read_material_vdb(dir.file("huge.vdb"));
        FAIL("the damaged file was read");
    } catch (const Error& e) {
        const std::string what = e.what();
        CHECK(what.find(dir.file("huge.vdb")) != std::string::npos);
        CHECK(what.find("its header asks for more memory") != std::string::npos);
        CHECK(what.find('\n') == std::string::npos);
    }
}

TEST_CASE("the contrast travels in the file, and clipped voxels come back with the same coefficients", "[vdb]") {
    TempDir dir;
    OpticalParams optics;
    optics.ks = {0.2, 0.1, 0.0};
    optics.contrast = {2.5, 0.5, 1.0};  // red clips at both ends; green is squeezed
    MaterialVolume v = sample_volume(16, optics);
    write_material_vdb(dir.file("v.vdb"), v);
    const MaterialVolume back = read_material_vdb(dir.file("v.vdb"));
    CHECK(back.optics.contrast == v.optics.contrast);
    CHECK(back.optics.mean_level == v.optics.mean_level);
    const CoefficientTable table(v.optics, v.cube.side);
    int clipped = 0;
    for (std::size_t i = 0; i < v.levels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const int a = v.levels[i][c], b = back.levels[i][c];
            CHECK(table.sigma_s[c][b] == Approx(table.sigma_s[c][a]).epsilon(1e-3).margin(1e-6));
            CHECK(table.sigma_a[c][b] == Approx(table.sigma_a[c][a]).epsilon(1e-3).margin(1e-6));
            const double vc = contrasted_level(a, c, v.optics);
            if (vc > 0.0 && vc < 1.0 && c != 1) CHECK(a == b);  // unclipped, unsqueezed: the level itself
            clipped += (vc == 0.0 || vc == 1.0);
        }
    CHECK(clipped > 0);
}

TEST_CASE("the noise's structure travels in the file and rebuilds the same levels", "[vdb]") {
    TempDir dir;
    NoiseParams marble;
    marble.frequency = 2.83, marble.k = 0.4, marble.stretch = 2.0, marble.angle = 30.0;
    marble.bands = 12.0, marble.warp = 0.7, marble.fold = 0.35;  // not the default 1
    // Veins and layers both: each flag changes the levels, so a flag lost
    // on the way would fail the rebuild below.
    marble.veins = GENERATE(false, true);
    marble.layers = GENERATE(false, true);
    marble.vein_frequency = 2.83, marble.vein_width = 0.01;  // not the defaults, so a lost value shows
    marble.sharpen = 1.5, marble.sharpen_radius = 0.8;  // likewise
    MaterialVolume v = sample_volume(16, OpticalParams{}, marble);
    v.structure = StructureMode::Photo;
    v.photo_span = 2.5;  // not the default 1
    write_material_vdb(dir.file("v.vdb"), v);
    const MaterialVolume back = read_material_vdb(dir.file("v.vdb"));
    require_same(v, back);
    // The stored parameters alone give the same volume again.
    CHECK(build_material_volume(sample_photo(), back.noise, back.match, back.optics).levels == v.levels);
}

TEST_CASE("a volume swept from the photo round-trips and rebuilds from its metadata", "[vdb]") {
    TempDir dir;
    NoiseParams swept;
    swept.exemplar = true, swept.exemplar_wander = 0.3, swept.seed = 7;  // not the defaults
    MaterialVolume v = sample_volume(16, OpticalParams{}, swept);
    v.structure = StructureMode::Exemplar;
    write_material_vdb(dir.file("v.vdb"), v);
    const MaterialVolume back = read_material_vdb(dir.file("v.vdb"));
    require_same(v, back);
    CHECK(build_material_volume(sample_photo(), back.noise, back.match, back.optics).levels == v.levels);
    // A structure the reader does not know is refused, naming the file and the metadata.
    auto [grids, meta] = read_all(dir.file("v.vdb"));
    meta->removeMeta("jade:structure");
    meta->insertMeta("jade:structure", openvdb::StringMetadata("marble"));
    openvdb::io::File(dir.file("bad.vdb")).write(*grids, *meta);
    CHECK_THROWS_WITH(read_material_vdb(dir.file("bad.vdb")),
                      Catch::Contains("bad.vdb") &&
                          Catch::Contains("metadata 'jade:structure' must be 'photo', 'exemplar' or 'fbm'"));
}

TEST_CASE("a file from before the fold reads with the isotropic warp it was made with", "[vdb]") {
    TempDir dir;
    NoiseParams layered;
    layered.layers = true, layered.bands = 12.0, layered.warp = 1.4, layered.frequency = 2.0;
    MaterialVolume v = sample_volume(16, OpticalParams{}, layered);
    v.structure = StructureMode::Photo;
    write_material_vdb(dir.file("v.vdb"), v);
    auto [grids, meta] = read_all(dir.file("v.vdb"));
    meta->removeMeta("jade:fold");
    openvdb::io::File(dir.file("before.vdb")).write(*grids, *meta);
    const MaterialVolume back = read_material_vdb(dir.file("before.vdb"));
    CHECK(back.noise.fold == 1.0);
    CHECK(build_material_volume(sample_photo(), back.noise, back.match, back.optics).levels == v.levels);
}

TEST_CASE("a file from before the photo's span reads at span 1, and a span out of range is refused", "[vdb]") {
    TempDir dir;
    MaterialVolume v = sample_volume(8, OpticalParams{});
    v.photo_span = 4.0;
    write_material_vdb(dir.file("v.vdb"), v);
    auto [grids, meta] = read_all(dir.file("v.vdb"));
    meta->removeMeta("jade:photo_span");
    openvdb::io::File(dir.file("before.vdb")).write(*grids, *meta);
    CHECK(read_material_vdb(dir.file("before.vdb")).photo_span == 1.0);
    meta->insertMeta("jade:photo_span", openvdb::DoubleMetadata(0.0));
    openvdb::io::File(dir.file("bad.vdb")).write(*grids, *meta);
    CHECK_THROWS_WITH(read_material_vdb(dir.file("bad.vdb")),
                      Catch::Contains("bad.vdb") && Catch::Contains("jade:photo_span") &&
                          Catch::Contains("must be between 0.125 and 8 cube sides, got 0"));
}

TEST_CASE("plain OpenVDB sees four fog-volume grids and the levels with the documented names, types and "
          "transform", "[vdb]") {
    TempDir dir;
    OpticalParams optics;
    optics.ks = {0.1, 0.2, -0.05};
    const MaterialVolume v = sample_volume(16, optics);
    write_material_vdb(dir.file("v.vdb"), v);

    openvdb::initialize();
    openvdb::io::File file(dir.file("v.vdb"));
    file.open();
    auto grids = file.getGrids();
    auto meta = file.getMetadata();
    file.close();
    REQUIRE(grids->size() == 5);

    std::map<std::string, openvdb::GridBase::Ptr> by_name;
    for (auto& g : *grids) by_name[g->getName()] = g;
    // The levels, packed r | g << 8 | b << 16, every voxel.
    auto levels = openvdb::gridPtrCast<openvdb::Int32Grid>(by_name["levels"]);
    REQUIRE(levels);
    const Rgb8 l = v.levels[v.index(5, 9, 15)];
    CHECK(levels->tree().getValue(openvdb::Coord(5, 9, 15)) == (l[0] | (l[1] << 8) | (l[2] << 16)));
    by_name.erase("levels");
    grids->erase(std::remove_if(grids->begin(), grids->end(), [](const auto& g) { return g->getName() == "levels"; }),
                 grids->end());
    auto ss = openvdb::gridPtrCast<openvdb::Vec3fGrid>(by_name["sigma_s"]);
    auto sa = openvdb::gridPtrCast<openvdb::Vec3fGrid>(by_name["sigma_a"]);
    auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(by_name["density"]);
    auto color = openvdb::gridPtrCast<openvdb::Vec3fGrid>(by_name["color"]);
    REQUIRE(ss);
    REQUIRE(sa);
    REQUIRE(density);
    REQUIRE(color);
    const double h = 3.0 / 16;
    for (auto& g : *grids) {
        CHECK(g->getGridClass() == openvdb::GRID_FOG_VOLUME);
        CHECK_FALSE(g->metaValue<std::string>("units").empty());
        CHECK_FALSE(g->metaValue<std::string>("description").empty());
        CHECK(g->activeVoxelCount() == 16u * 16u * 16u);
        // Voxel (i,j,k) centred at cube.min + (i + 1/2) h.
        const openvdb::Vec3d p0 = g->indexToWorld(openvdb::Vec3d(0, 0, 0));
        CHECK(p0.x() == Approx(-1.0 + 0.5 * h));
        CHECK(p0.y() == Approx(0.5 + 0.5 * h));
        CHECK(p0.z() == Approx(2.0 + 0.5 * h));
        CHECK(g->voxelSize().x() == Approx(h));
        CHECK(g->evalActiveVoxelBoundingBox() ==
              openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(15)));
    }

    // Values: the documented formulas, to half-float precision.
    const CoefficientTable table(v.optics, v.cube.side);
    for (const openvdb::Coord xyz : {openvdb::Coord(0, 0, 0), openvdb::Coord(5, 9, 15)}) {
        const Rgb8 lv = v.levels[v.index(xyz.x(), xyz.y(), xyz.z())];
        const auto s = ss->tree().getValue(xyz), a = sa->tree().getValue(xyz),
                   alb = color->tree().getValue(xyz);
        double mean_t = 0;
        for (int c = 0; c < 3; ++c) {
            const double want_s = paper_sigma_s(lv[c], c, v.optics) * 20.0 / 3.0;
            const double want_a = paper_sigma_a(lv[c], c, v.optics) * 20.0 / 3.0;
            CHECK(s[c] == Approx(want_s).epsilon(1e-3).margin(1e-6));
            CHECK(a[c] == Approx(want_a).epsilon(1e-3).margin(1e-6));
            CHECK(alb[c] == Approx(want_s / (want_s + want_a)).epsilon(2e-3));
            mean_t += (want_s + want_a) / 3.0;
        }
        CHECK(density->tree().getValue(xyz) == Approx(mean_t).epsilon(1e-3));
    }

    for (const char* key : {"jade:format", "jade:format_version", "jade:jaderender_version",
                            "jade:photo", "jade:resolution", "jade:octaves", "jade:k", "jade:seed",
                            "jade:match", "jade:ds", "jade:da", "jade:ks", "jade:density_scale",
                            "jade:cube_min", "jade:cube_side", "jade:units", "jade:up_axis", "jade:masked"}) {
        INFO(key);
        CHECK((*meta)[key]);
    }
    CHECK(meta->metaValue<std::string>("jade:match") == "joint");
    CHECK(meta->metaValue<openvdb::Vec3d>("jade:ks") == openvdb::Vec3d(0.1, 0.2, -0.05));
}

TEST_CASE("reading a file that is not a jaderender volume is one clear error", "[vdb]") {
    TempDir dir;
    CHECK_THROWS_WITH(read_material_vdb(dir.file("none.vdb")), Catch::Contains("no such file"));
    std::ofstream(dir.file("junk.vdb")) << "this is not a vdb";
    CHECK_THROWS_WITH(read_material_vdb(dir.file("junk.vdb")), Catch::Contains("junk.vdb"));

    openvdb::initialize();
    auto g = openvdb::FloatGrid::create(0.f);
    g->setName("density");
    openvdb::io::File(dir.file("foreign.vdb")).write({g});
    CHECK_THROWS_WITH(read_material_vdb(dir.file("foreign.vdb")), Catch::Contains("foreign.vdb"));

    // Grids edited after writing no longer follow from the metadata.
    const MaterialVolume v = sample_volume(8, OpticalParams{});
    write_material_vdb(dir.file("v.vdb"), v);
    auto [grids, meta] = read_all(dir.file("v.vdb"));
    for (auto& base : *grids)
        if (base->getName() == "sigma_s")
            openvdb::gridPtrCast<openvdb::Vec3fGrid>(base)->tree().setValue(
                openvdb::Coord(1, 2, 3), openvdb::Vec3f(99.f));
    openvdb::io::File(dir.file("edited.vdb")).write(*grids, *meta);
    CHECK_THROWS_WITH(read_material_vdb(dir.file("edited.vdb")),
                      Catch::Contains("do not follow from"));
}

// ---------------------------------------------------------------------------
// Foreign .vdb media (the renderer's --volume with another tool's grids)

namespace {

// Writes `grids` (all sharing one transform: voxel size h, offset) to path.
void write_grids(const std::string& path, const openvdb::GridPtrVec& grids) {
    openvdb::io::File(path).write(grids);
}

openvdb::math::Transform::Ptr placement(double h, openvdb::Vec3d offset) {
    auto xf = openvdb::math::Transform::createLinearTransform(h);
    xf->postTranslate(offset);
    return xf;
}

}  // namespace

TEST_CASE("foreign density + color grids become coefficients in world space", "[vdb]") {
    openvdb::initialize();
    TempDir dir;
    const auto xf = placement(0.25, {1.0, 0.0, -2.0});
    auto density = openvdb::FloatGrid::create(0.f);
    density->setName("density");
    density->setTransform(xf);
    auto color = openvdb::Vec3fGrid::create(openvdb::Vec3f(0.f));
    color->setName("color");
    color->setTransform(xf);
    // Active voxels (2..4, 1..2, 0..0): density = i, color = (0.5, 1, 0).
    for (int i = 2; i <= 4; ++i)
        for (int j = 1; j <= 2; ++j) {
            density->tree().setValue(openvdb::Coord(i, j, 0), float(i));
            color->tree().setValue(openvdb::Coord(i, j, 0), openvdb::Vec3f(0.5f, 1.f, 0.f));
        }
    write_grids(dir.file("d.vdb"), {density, color});
    CHECK_FALSE(is_material_vdb(dir.file("d.vdb")));

    DensityConversion conv;
    conv.scale = 10.f;
    const CoefficientGrids g = read_medium_vdb(dir.file("d.vdb"), conv);
    // Dense over the active bounding box; voxel (2, 1, 0) is centred at offset + (2, 1, 0) h.
    CHECK(g.placement.size == std::array<int, 3>{3, 2, 1});
    CHECK(g.placement.origin.x == Approx(1.5f));
    CHECK(g.placement.origin.y == Approx(0.25f));
    CHECK(g.placement.origin.z == Approx(-2.f));
    CHECK(g.placement.spacing.x == Approx(0.25f));
    // σ_t = 10 · density, σ_s = albedo · σ_t, σ_a = (1 − albedo) · σ_t.
    const Spectrum s = g.sigma_s[(0 * 2 + 1) * 3 + 2];  // voxel (4, 2, 0)
    const Spectrum a = g.sigma_a[(0 * 2 + 1) * 3 + 2];
    CHECK(s.x == Approx(20.f));
    CHECK(s.y == Approx(40.f));
    CHECK(s.z == Approx(0.f));
    CHECK(a.x == Approx(20.f));
    CHECK(a.z == Approx(40.f));

    // Houdini names the albedo `Cd`: the same medium.
    color->setName("Cd");
    write_grids(dir.file("cd.vdb"), {density, color});
    const CoefficientGrids h = read_medium_vdb(dir.file("cd.vdb"), conv);
    CHECK(h.sigma_s[(0 * 2 + 1) * 3 + 2].y == Approx(40.f));
    CHECK(h.sigma_a[(0 * 2 + 1) * 3 + 2].z == Approx(40.f));

    // Without a color grid the albedo comes from the conversion.
    write_grids(dir.file("d2.vdb"), {density});
    conv.albedo = Spectrum(0.25f);
    const CoefficientGrids g2 = read_medium_vdb(dir.file("d2.vdb"), conv);
    CHECK(g2.sigma_s[0].x == Approx(0.25f * 20.f));
    CHECK(g2.sigma_a[0].x == Approx(0.75f * 20.f));
}

TEST_CASE("foreign sigma grids may be float, rotated or missing grids are refused", "[vdb]") {
    openvdb::initialize();
    TempDir dir;
    const auto xf = placement(0.5, {0.0, 0.0, 0.0});
    auto ss = openvdb::FloatGrid::create(0.f);
    ss->setName("sigma_s");
    ss->setTransform(xf);
    auto sa = openvdb::Vec3fGrid::create(openvdb::Vec3f(0.f));
    sa->setName("sigma_a");
    sa->setTransform(xf);
    ss->tree().setValue(openvdb::Coord(0, 0, 0), 3.f);
    sa->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3f(1.f, 2.f, 3.f));
    write_grids(dir.file("s.vdb"), {ss, sa});
    const CoefficientGrids g = read_medium_vdb(dir.file("s.vdb"), {});
    CHECK(g.sigma_s[0] == Spectrum(3.f));
    CHECK(g.sigma_a[0] == Spectrum(1.f, 2.f, 3.f));

    auto rotated = ss->deepCopy();
    auto rx = openvdb::math::Transform::createLinearTransform(0.5);
    rx->postRotate(0.3, openvdb::math::Y_AXIS);
    rotated->setTransform(rx);
    auto sa2 = sa->deepCopy();
    sa2->setTransform(rx);
    write_grids(dir.file("r.vdb"), {rotated, sa2});
    CHECK_THROWS_WITH(read_medium_vdb(dir.file("r.vdb"), {}), Catch::Contains("axis-aligned"));

    auto other = openvdb::FloatGrid::create(0.f);
    other->setName("temperature");
    other->tree().setValue(openvdb::Coord(0, 0, 0), 1.f);
    write_grids(dir.file("t.vdb"), {other});
    CHECK_THROWS_WITH(read_medium_vdb(dir.file("t.vdb"), {}), Catch::Contains("t.vdb"));
}

TEST_CASE("masked to a mesh and turned Z-up: the coefficient grids cover the interior, the levels the cube",
          "[vdb]") {
    TempDir dir;
    const MaterialVolume v = sample_volume(32, OpticalParams{});
    // A sphere inscribed in the cube (centre (0.5, 2, 3.5), radius 1.5).
    TriangleMesh sphere = icosphere(4, 1.5f);
    for (glm::vec3& p : sphere.positions) p += glm::vec3(0.5f, 2.f, 3.5f);
    write_material_vdb(dir.file("m.vdb"), v, VdbLayout{&sphere, true, "Cd"});
    // jaderender reads the same material, whole.
    require_same(v, read_material_vdb(dir.file("m.vdb")));
    CHECK_THROWS_WITH(write_material_vdb(dir.file("x.vdb"), v, VdbLayout{nullptr, false, "albedo"}),
                      Catch::Contains("'color' (Blender) or 'Cd' (Houdini)"));

    openvdb::io::File file(dir.file("m.vdb"));
    file.open();
    auto grids = file.getGrids();
    auto meta = file.getMetadata();
    file.close();
    CHECK(meta->metaValue<std::string>("jade:up_axis") == "z");
    std::set<std::string> names;
    for (auto& g : *grids) names.insert(g->getName());
    CHECK(names == std::set<std::string>{"Cd", "density", "levels", "sigma_a", "sigma_s", "surface_distance"});
    const double h = 3.0 / 32;
    for (auto& g : *grids) {
        INFO(g->getName());
        if (g->getName() == "levels") {
            CHECK(g->activeVoxelCount() == 32u * 32u * 32u);
            continue;
        }
        if (g->getName() == "surface_distance") {
            // Near the surface the sphere's own signed distance (Z-up world:
            // the centre (0.5, 2, 3.5) is at (0.5, -3.5, 2)), to a tenth of a
            // voxel plus the icosphere's facets (< 0.005); negative deep inside.
            const auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g);
            int near = 0;
            for (auto it = f->cbeginValueOn(); it; ++it) {
                const double exact = (f->indexToWorld(it.getCoord()) - openvdb::Vec3d(0.5, -3.5, 2.0)).length() - 1.5;
                if (std::abs(exact) > 1.5 * h) continue;
                ++near;
                CHECK(*it == Approx(exact).margin(0.1 * h + 0.005));
            }
            CHECK(near > 1000);
            CHECK(f->tree().getValue(openvdb::Coord(16, 16, 16)) < 0.f);
        }
        // The sphere holds pi/6 of the cube; growing it by a voxel (faces,
        // edges and corners: 1 to sqrt(3) voxels deep) adds its area times
        // less than 2 voxels on average.
        const double share = double(g->activeVoxelCount()) / (32.0 * 32.0 * 32.0);
        CHECK(share > 0.5236 * 0.97);
        CHECK(share < 0.5236 + 4.0 * M_PI * 1.5 * 1.5 * 2.0 * h / 27.0);
        // The centre voxel (16, 16, 16) is active, a corner not.
        auto on = [&](const openvdb::Coord& xyz) {
            if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g)) return f->tree().isValueOn(xyz);
            return openvdb::gridPtrCast<openvdb::Vec3fGrid>(g)->tree().isValueOn(xyz);
        };
        CHECK(on(openvdb::Coord(16, 16, 16)));
        CHECK_FALSE(on(openvdb::Coord(0, 0, 0)));
        // Z-up: the Y-up centre (x, y, z) of voxel (0, 0, 0) lands at (x, -z, y).
        const openvdb::Vec3d p0 = g->indexToWorld(openvdb::Vec3d(0, 0, 0));
        CHECK(p0.x() == Approx(-1.0 + 0.5 * h));
        CHECK(p0.y() == Approx(-(2.0 + 0.5 * h)));
        CHECK(p0.z() == Approx(0.5 + 0.5 * h));
    }
}

TEST_CASE("a format 1 file (no levels grid) still reads: levels recovered from the coefficients", "[vdb]") {
    TempDir dir;
    OpticalParams paper;  // files of that format have §5.1's extinction and no key for it
    paper.extinction = Extinction::Paper;
    paper.ks = {0.3, -0.2, 1.5};
    paper.da = 0.25;
    for (const OpticalParams& optics : {OpticalParams{}, paper}) {
        const MaterialVolume v = sample_volume(16, optics);
        write_material_vdb(dir.file("v.vdb"), v);
        auto [grids, meta] = read_all(dir.file("v.vdb"));
        grids->erase(
            std::remove_if(grids->begin(), grids->end(), [](const auto& g) { return g->getName() == "levels"; }),
            grids->end());
        meta->removeMeta("jade:format_version");
        meta->insertMeta("jade:format_version", openvdb::Int32Metadata(1));
        if (optics.extinction == Extinction::Paper) meta->removeMeta("jade:extinction");
        openvdb::io::File(dir.file("v1.vdb")).write(*grids, *meta);
        require_same(v, read_material_vdb(dir.file("v1.vdb")));
    }
}

TEST_CASE("the extinction travels in the file, and a file without it has §5.1's", "[vdb]") {
    TempDir dir;
    OpticalParams fitted;
    fitted.ks = {2.0, 1.0, 0.3};  // grey and §5.1's extinctions differ where k_s is not 0
    MaterialVolume v = sample_volume(12, fitted);
    write_material_vdb(dir.file("grey.vdb"), v);
    const MaterialVolume grey = read_material_vdb(dir.file("grey.vdb"));
    CHECK(grey.optics.extinction == Extinction::Grey);
    // Grey: the density grid (the mean σ_t) is d_s · density_scale / side in every voxel.
    auto [grids, meta] = read_all(dir.file("grey.vdb"));
    for (const auto& g : *grids)
        if (g->getName() == "density") {
            const auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(g);
            for (auto it = density->cbeginValueOn(); it; ++it)
                REQUIRE(*it == Approx(fitted.density_scale / 3.0).epsilon(1e-3));
        }
    // An earlier version's file: no key, §5.1's extinction, and its grids say so.
    v.optics.extinction = Extinction::Paper;
    write_material_vdb(dir.file("paper.vdb"), v);
    auto [paper_grids, paper_meta] = read_all(dir.file("paper.vdb"));
    paper_meta->removeMeta("jade:extinction");
    openvdb::io::File(dir.file("old.vdb")).write(*paper_grids, *paper_meta);
    CHECK(read_material_vdb(dir.file("old.vdb")).optics.extinction == Extinction::Paper);
    // A key with another value is refused with the file's name.
    paper_meta->removeMeta("jade:extinction");
    paper_meta->insertMeta("jade:extinction", openvdb::StringMetadata("purple"));
    openvdb::io::File(dir.file("bad.vdb")).write(*paper_grids, *paper_meta);
    CHECK_THROWS_WITH(read_material_vdb(dir.file("bad.vdb")), Catch::Contains("bad.vdb") && Catch::Contains("extinction"));
}
