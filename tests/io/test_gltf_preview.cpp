// preview.glb's material against the slab it stands for, and the file read
// back by our glTF reader (the Khronos validator checks the pipeline's
// preview in the regression tests).

#include "jade/geometry/mesh_io.h"
#include "jade/io/gltf_preview.h"
#include "jade/volume/slab_reflectance.h"

#include "support/test_util.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

using namespace jade;
using jade_test::TempDir;

TEST_CASE("glTF preview: a viewer's diffuse and transmitted parts are the slab's R and T", "[preview]") {
    // A jade-like medium: much scattering, absorption rising towards blue.
    const std::array<double, 3> ss{30.0, 25.0, 12.0}, sa{0.2, 0.6, 2.5};
    const double d = 0.8;
    const GltfPreviewMaterial m = gltf_preview_material(ss, sa, 0.3, 1.6, d);
    CHECK(m.thickness == d);
    CHECK(m.attenuation_distance == d);
    CHECK(m.ior == 1.6);
    REQUIRE(m.transmission > 0.0);
    REQUIRE(m.transmission < 1.0);
    double largest = 0.0;
    for (int c = 0; c < 3; ++c) {
        const SlabReflectance s = kubelka_munk_slab(kubelka_munk_coefficients(ss[c], sa[c], 0.3), d);
        CHECK(m.slab_R[c] == s.R);
        CHECK(m.slab_T[c] == s.T);
        REQUIRE(m.base_color[c] < 1.0);  // not clipped for this medium
        CHECK((1 - m.transmission) * m.base_color[c] == Approx(s.R).epsilon(1e-12));
        CHECK(m.transmission * m.base_color[c] * m.attenuation_color[c] == Approx(s.T).epsilon(1e-12));
        CHECK(m.attenuation_color[c] <= 1.0);
        largest = std::max(largest, m.attenuation_color[c]);
    }
    CHECK(largest == Approx(1.0));  // the most transmissive channel sets the transmission
    // Clear glass: no scattering, all transmitted, absorbed along the way.
    const GltfPreviewMaterial glass = gltf_preview_material({0, 0, 0}, {0.1, 0.2, 0.4}, 0.0, 1.5, 1.0);
    CHECK(glass.transmission == 1.0);
    CHECK(glass.base_color[0] == 1.0);
    CHECK(glass.attenuation_color[2] == Approx(std::exp(-0.8)));
    CHECK_THROWS(gltf_preview_material(ss, sa, 0.0, 1.6, 0.0));
}

TEST_CASE("glTF preview: the file holds the mesh and the material's extensions", "[preview]") {
    TempDir dir;
    const TriangleMesh mesh = icosphere(2, 0.5f);
    const GltfPreviewMaterial m = gltf_preview_material({10, 8, 6}, {0.1, 0.3, 0.9}, 0.0, 1.6, mean_chord_length(mesh));
    const std::string path = dir.file("p.glb");
    write_preview_glb(path, mesh, m);

    const TriangleMesh back = load_mesh(path);
    REQUIRE(back.triangles.size() == mesh.triangles.size());
    REQUIRE(back.positions.size() == mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) REQUIRE(back.positions[i] == mesh.positions[i]);

    // The JSON chunk: 12-byte header, then chunk length and type "JSON".
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(bytes.substr(0, 4) == "glTF");
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, bytes.data() + 12, 4);
    REQUIRE(bytes.substr(16, 4) == "JSON");
    const nlohmann::json j = nlohmann::json::parse(bytes.substr(20, json_length));
    const auto& used = j.at("extensionsUsed");
    for (const char* ext : {"KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"})
        CHECK(std::find(used.begin(), used.end(), ext) != used.end());
    const auto& mat = j.at("materials").at(0);
    CHECK(mat.at("extensions").at("KHR_materials_transmission").at("transmissionFactor").get<double>() ==
          Approx(m.transmission));
    CHECK(mat.at("extensions").at("KHR_materials_volume").at("thicknessFactor").get<double>() ==
          Approx(m.thickness));
    CHECK(mat.at("extensions").at("KHR_materials_ior").at("ior").get<double>() == Approx(1.6));
    CHECK(mat.at("pbrMetallicRoughness").at("baseColorFactor").at(2).get<double>() == Approx(m.base_color[2]));
    // The mean chord of a sphere is 4r/3 (the icosphere's a little less).
    CHECK(mean_chord_length(mesh) == Approx(4 * 0.5 / 3).epsilon(0.02));
}
