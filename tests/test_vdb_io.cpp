// The .vdb file: exact round trip, and what plain OpenVDB sees in it.

#include "jade/error.h"
#include "jade/material_volume.h"
#include "jade/vdb_io.h"

#include "test_util.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>

#include <fstream>

using namespace jade;
using jade_test::TempDir;

namespace {

MaterialVolume sample_volume(int s, OpticalParams optics) {
    Photo photo;
    photo.path = "stone.png";
    photo.width = 32;
    photo.height = 32;
    for (int i = 0; i < 1024; ++i) {
        photo.levels.push_back(
            {std::uint8_t(i % 256), std::uint8_t((i * 7) % 256), std::uint8_t(255 - i % 256)});
        photo.foreground.push_back(1);
    }
    NoiseParams n;
    n.resolution = s;
    n.seed = 11;
    MaterialVolume v = build_material_volume(photo, n, MatchMode::Joint, optics);
    v.cube.min = {-1.0, 0.5, 2.0};
    v.cube.side = 3.0;
    return v;
}

void require_same(const MaterialVolume& a, const MaterialVolume& b) {
    REQUIRE(a.resolution == b.resolution);
    CHECK(a.levels == b.levels);
    CHECK(a.noise.octave_count() == b.noise.octave_count());
    CHECK(a.noise.k == b.noise.k);
    CHECK(a.noise.seed == b.noise.seed);
    CHECK(a.match == b.match);
    CHECK(a.optics.ds == b.optics.ds);
    CHECK(a.optics.da == b.optics.da);
    CHECK(a.optics.ks == b.optics.ks);
    CHECK(a.optics.density_scale == b.optics.density_scale);
    CHECK(a.cube.min == b.cube.min);
    CHECK(a.cube.side == b.cube.side);
    CHECK(a.photo == b.photo);
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
    for (const OpticalParams& optics : {defaults, fitted, no_absorption}) {
        // 20 is not a multiple of the 8-voxel leaf: partial leaves too.
        const MaterialVolume v = sample_volume(20, optics);
        write_material_vdb(dir.file("v.vdb"), v);
        require_same(v, read_material_vdb(dir.file("v.vdb")));
    }
}

TEST_CASE("plain OpenVDB sees four fog-volume grids with the documented names, types and "
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
    REQUIRE(grids->size() == 4);

    std::map<std::string, openvdb::GridBase::Ptr> by_name;
    for (auto& g : *grids) by_name[g->getName()] = g;
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
            const double want_a = paper_sigma_a(lv[c], v.optics) * 20.0 / 3.0;
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
                            "jade:cube_min", "jade:cube_side", "jade:units"}) {
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
    openvdb::io::File f(dir.file("v.vdb"));
    f.open();
    auto grids = f.getGrids();
    auto meta = f.getMetadata();
    f.close();
    for (auto& base : *grids)
        if (base->getName() == "sigma_s")
            openvdb::gridPtrCast<openvdb::Vec3fGrid>(base)->tree().setValue(
                openvdb::Coord(1, 2, 3), openvdb::Vec3f(99.f));
    openvdb::io::File(dir.file("edited.vdb")).write(*grids, *meta);
    CHECK_THROWS_WITH(read_material_vdb(dir.file("edited.vdb")),
                      Catch::Contains("do not follow from"));
}
