// Meshes: real files load with the documented triangle counts and closed
// topology; synthetic OBJ files check normals, holes and bad input.

#include "jade/core/error.h"
#include "jade/geometry/mesh_io.h"
#include "jade/geometry/topology.h"

#include "support/test_util.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <fstream>

using namespace jade;
using jade_test::TempDir;

namespace {

// Axis-aligned cube [-1, 1]^3, outward counter-clockwise winding, as OBJ text.
// drop_top = true leaves the +z face out (an open box).
std::string cube_obj(bool drop_top = false, bool with_normals = false) {
    std::string s =
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n";
    if (with_normals) s += "vn 0 0 1\n";
    const char* faces[] = {"1 4 3 2", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8"};
    for (int f = 0; f < 6; ++f) {
        if (drop_top && f == 1) continue;
        std::string face = faces[f];
        if (with_normals) {
            std::string out;
            for (char c : face) out += c == ' ' ? std::string("//1 ") : std::string(1, c);
            face = out + "//1";
        }
        s += "f " + face + "\n";
    }
    return s;
}

}  // namespace

TEST_CASE("demo meshes load closed, outward, with the documented triangle counts", "[mesh]") {
    struct Expect {
        const char* file;
        std::size_t triangles;
    };
    for (const Expect e : {Expect{"greek-vase-01.glb", 2936}, Expect{"spot-cow.obj", 23062},
                           Expect{"stanford-bunny-watertight-70k.obj", 69664}}) {
        INFO(e.file);
        const TriangleMesh m = load_mesh(std::string(JADE_DATA_DIR "/meshes/") + e.file);
        CHECK(m.triangles.size() == e.triangles);
        CHECK(m.normals.size() == m.positions.size());
        const MeshTopology topo = mesh_topology(m);
        CHECK(topo.closed());
        CHECK(signed_volume(m) > 0.0);  // outward winding
    }
}

TEST_CASE("an OBJ cube: exact bounds, cube, computed smooth normals", "[mesh]") {
    TempDir dir;
    std::ofstream(dir.file("cube.obj")) << cube_obj();
    const TriangleMesh m = load_mesh(dir.file("cube.obj"));
    REQUIRE(m.triangles.size() == 12);
    CHECK_FALSE(m.file_normals);
    CHECK(signed_volume(m) == Approx(8.0));  // the cube's volume, by the divergence theorem
    TriangleMesh inside_out = m;
    reverse_orientation(inside_out);
    CHECK(signed_volume(inside_out) == Approx(-8.0));
    CHECK(glm::dot(inside_out.normals[0], m.normals[0]) == Approx(-1.f));
    TriangleMesh far = m;  // far from the origin: no cancellation
    for (auto& p : far.positions) p += glm::vec3(1e4f, -2e4f, 3e4f);
    CHECK(signed_volume(far) == Approx(8.0).epsilon(1e-6));
    const MeshTopology topo = mesh_topology(m);
    CHECK(topo.closed());
    CHECK(topo.edges == 18);  // 12 cube edges + 6 face diagonals
    // A corner's area-weighted normal points along the diagonal.
    for (std::size_t v = 0; v < m.positions.size(); ++v)
        CHECK(glm::dot(m.normals[v], glm::normalize(m.positions[v])) > 0.5f);
    const Cube c = bounding_cube(m);
    CHECK(c.side == 2.0);
    CHECK(c.min == std::array<double, 3>{-1.0, -1.0, -1.0});
}

TEST_CASE("the bounding cube is centred on the box, side = longest extent", "[mesh]") {
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {4, 0, 0}, {0, 2, 1}};
    m.triangles = {{0, 1, 2}};
    const Cube c = bounding_cube(m);
    CHECK(c.side == 4.0);
    CHECK(c.min[0] == 0.0);
    CHECK(c.min[1] == -1.0);   // centre 1, minus 2
    CHECK(c.min[2] == -1.5);   // centre 0.5, minus 2
}

TEST_CASE("file normals are used when every corner has one", "[mesh]") {
    TempDir dir;
    std::ofstream(dir.file("n.obj")) << cube_obj(false, true);
    const TriangleMesh m = load_mesh(dir.file("n.obj"));
    CHECK(m.file_normals);
    for (const auto& n : m.normals) CHECK(n == glm::vec3(0, 0, 1));
}

TEST_CASE("a NaN vertex is refused, naming the file", "[mesh]") {
    // Binary glTF can carry NaN coordinates (OBJ text cannot: tinyobjloader
    // reads "nan" as 0), so the check runs on the loaded mesh for every format.
    TriangleMesh m;
    m.path = "broken.glb";
    m.positions = {{0, 0, 0}, {1, 0, 0}, {std::nanf(""), 1, 0}};
    m.triangles = {{0, 1, 2}};
    CHECK_THROWS_WITH(validate_mesh(m), Catch::Contains("broken.glb") && Catch::Contains("NaN"));
    m.positions[2] = {0, 1, 0};
    CHECK_NOTHROW(validate_mesh(m));
}

TEST_CASE("an open box is reported with its hole", "[mesh]") {
    TempDir dir;
    std::ofstream(dir.file("open.obj")) << cube_obj(true);
    const MeshTopology topo = mesh_topology(load_mesh(dir.file("open.obj")));
    CHECK_FALSE(topo.closed());
    CHECK(topo.boundary_edges == 4);
    CHECK(topo.nonmanifold_edges == 0);
}

TEST_CASE("bad meshes are one clear error naming the file", "[mesh]") {
    TempDir dir;
    CHECK_THROWS_WITH(load_mesh(dir.file("none.obj")), Catch::Contains("no such file"));
    std::ofstream(dir.file("empty.obj")) << "# nothing\nv 0 0 0\n";
    CHECK_THROWS_WITH(load_mesh(dir.file("empty.obj")), Catch::Contains("no triangle"));
    std::ofstream(dir.file("flat.obj")) << "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n";
    CHECK_THROWS_WITH(load_mesh(dir.file("flat.obj")), Catch::Contains("zero size"));
    std::ofstream(dir.file("m.stl")) << "solid";
    CHECK_THROWS_WITH(load_mesh(dir.file("m.stl")), Catch::Contains("unknown mesh format"));
    std::ofstream(dir.file("bad.glb")) << "glTF garbage";
    CHECK_THROWS_WITH(load_mesh(dir.file("bad.glb")), Catch::Contains("bad.glb"));
}

TEST_CASE("the built-in icosphere is closed, outward-wound and on the sphere", "[mesh]") {
    const TriangleMesh m = icosphere(3, 2.f);
    CHECK(m.triangles.size() == 20u * 64u);
    CHECK(mesh_topology(m).closed());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const auto& tri = m.triangles[t];
        const glm::vec3 c = (m.positions[tri[0]] + m.positions[tri[1]] + m.positions[tri[2]]) / 3.f;
        REQUIRE(glm::dot(m.face_normal(t), c) > 0.f);
    }
    for (const auto& p : m.positions) REQUIRE(glm::length(p) == Approx(2.f));
}

TEST_CASE("convexity: a sphere and a cube are convex but the cow, two spheres and an open box are not", "[mesh]") {
    CHECK(is_convex(icosphere(3, 1.f)));
    TempDir dir;
    std::ofstream(dir.file("cube.obj")) << cube_obj();
    const TriangleMesh cube = load_mesh(dir.file("cube.obj"));
    CHECK(is_convex(cube));
    CHECK_FALSE(is_convex(load_mesh(JADE_DATA_DIR "/meshes/spot-cow.obj")));
    CHECK_FALSE(is_convex(load_mesh(JADE_DATA_DIR "/reference/blob.obj")));
    // Two disjoint spheres: each locally convex everywhere, together not convex.
    TriangleMesh two = icosphere(2, 1.f);
    const TriangleMesh other = icosphere(2, 1.f);
    const auto offset = std::uint32_t(two.positions.size());
    for (const auto& p : other.positions) two.positions.push_back(p + glm::vec3(3.f, 0.f, 0.f));
    for (const auto& n : other.normals) two.normals.push_back(n);
    for (const auto& t : other.triangles) two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    CHECK_FALSE(is_convex(two));
    // The cube without one face is open.
    TriangleMesh open = cube;
    open.triangles.resize(10);
    CHECK_FALSE(is_convex(open));
    // A dent: one vertex of the sphere pushed inward.
    TriangleMesh dented = icosphere(3, 1.f);
    dented.positions[0] *= 0.9f;
    CHECK_FALSE(is_convex(dented));
}
