// A manifest of fits: read from JSON or CSV with its paths resolved, turned
// into the pipeline's flags per entry, and gathered back from the entries'
// report.json files into one table.

#include "jade/app/batch.h"
#include "jade/core/error.h"
#include "jade/io/image_io.h"

#include "support/test_util.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jade;
using jade_test::TempDir;

namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

TEST_CASE("a JSON manifest: paths relative to it, common flags before the entry's", "[batch]") {
    TempDir dir;
    std::ofstream(dir.file("m.json")) << R"({"flags": ["--resolution", "64"],
        "entries": [{"photo": "p/a.jpg", "mesh": "/abs/vase.glb", "out": "out/a", "flags": ["--fit", "bisect"]},
                    {"photo": "b.png", "mask": "b-mask.png", "mesh": "cow.obj"}]})";
    const BatchManifest m = load_manifest(dir.file("m.json"));
    REQUIRE(m.entries.size() == 2);
    CHECK(entry_arguments(m, 0) == std::vector<std::string>{"--photo", dir.file("p/a.jpg"), "--mesh", "/abs/vase.glb",
                                                            "--out", dir.file("out/a"), "--resolution", "64", "--fit",
                                                            "bisect"});
    // No "out": <photo stem>-<mesh stem> beside the manifest.
    CHECK(entry_arguments(m, 1) == std::vector<std::string>{"--photo", dir.file("b.png"), "--mesh", dir.file("cow.obj"),
                                                            "--out", dir.file("b-cow"), "--mask", dir.file("b-mask.png"),
                                                            "--resolution", "64"});
    CHECK_THROWS_WITH(entry_arguments(m, 2), Catch::Contains("--index 2 is not an entry") && Catch::Contains("0 to 1"));
    CHECK_THROWS_AS(entry_arguments(m, -1), Error);
}

TEST_CASE("a CSV manifest reads the same, and bad manifests are refused with one line", "[batch]") {
    TempDir dir;
    std::ofstream(dir.file("m.csv")) << "photo,mask,mesh,out,flags\r\na.jpg,,vase.glb,out/a,--fit bisect --seed 3\n\n"
                                        "b.jpg,m.png,cow.obj,,\n";
    const BatchManifest m = load_manifest(dir.file("m.csv"));
    REQUIRE(m.entries.size() == 2);
    CHECK(m.entries[0].flags == std::vector<std::string>{"--fit", "bisect", "--seed", "3"});
    CHECK(m.entries[1].mask == dir.file("m.png"));
    CHECK(m.entries[1].out == dir.file("b-cow"));

    auto refused = [&](const std::string& name, const std::string& text, const std::string& words) {
        std::ofstream(dir.file(name)) << text;
        CHECK_THROWS_WITH(load_manifest(dir.file(name)), Catch::Contains(name) && Catch::Contains(words));
    };
    refused("h.csv", "photo,mesh\na.jpg,v.glb\n", "header photo,mask,mesh,out,flags");
    refused("c.csv", "photo,mask,mesh,out,flags\na.jpg,v.glb\n", "line 2 has 2 cells");
    refused("e.json", R"({"entries": []})", "no entries");
    refused("n.json", R"({"entries": [{"photo": "a.jpg"}]})", "entry 0: names no photo or no mesh");
    refused("r.json", R"({"entries": [{"photo": "a.jpg", "mesh": "v.glb", "flags": ["render"]}]})",
            "names a command");
    refused("t.json", R"({"entries": [{"photo": 3, "mesh": "v.glb"}]})", "not a manifest");
    refused("x.json", "{", "not a manifest");
    CHECK_THROWS_WITH(load_manifest(dir.file("none.json")), Catch::Contains("none.json: no such file"));
}

TEST_CASE("the summary gathers every report.json, and says which are missing", "[batch]") {
    TempDir dir;
    std::ofstream(dir.file("m.json")) << R"({"entries": [{"photo": "a.jpg", "mesh": "v.glb", "out": "a"},
        {"photo": "b.jpg", "mesh": "v.glb", "out": "b"}, {"photo": "c.jpg", "mesh": "v.glb", "out": "c"}]})";
    std::filesystem::create_directories(dir.file("a"));
    std::filesystem::create_directories(dir.file("c"));
    std::ofstream(dir.file("a/report.json")) << R"({"fit": {"converged": true, "method": "contrast", "renders": 7,
        "exposure": 2.5, "ks": [1.5, 2, 2.25], "contrast": [1, 1.25, 3]},
        "appearance": {"A_photo": [180, 140, 100], "A_render": [181, 139, 101], "S_photo": [14, 19, 23],
                       "S_render": [15, 18, 24], "D": [0.01, 0.02, 0.03], "structure_distance": 0.25,
                       "structure_distance_error": 0.0625},
        "final_render": {"estimated_relative_error": 0.125, "spp": 256}, "seconds": {"total": 61.5},
        "peak_memory_bytes": 1000})";
    std::ofstream(dir.file("c/report.json")) << "{ cut short";
    const BatchManifest m = load_manifest(dir.file("m.json"));
    const BatchSummary s = write_batch_summary(m, dir.file("summary.csv"));
    CHECK(s.done == 1);
    CHECK(s.missing == 2);
    const std::string csv = slurp(dir.file("summary.csv"));
    CHECK_THAT(csv, Catch::StartsWith("index,photo,mesh,out,status,converged,fit,renders,exposure,ks_r,ks_g,ks_b,"));
    CHECK_THAT(csv, Catch::Contains(",done,1,contrast,7,2.5,1.5,2,2.25,1,1.25,3,180,140,100,181,139,101,14,19,23,15,18,"
                                    "24,0.01,0.02,0.03,0.25,0.0625,0.125,256,61.5,1000\n"));
    CHECK_THAT(csv, Catch::Contains(dir.file("b") + ",missing,"));
    CHECK_THAT(csv, Catch::Contains(dir.file("c") + ",unreadable,"));

    // The contact sheet: one cell per entry in a 2 x 2 grid; entries without
    // a compare.png are grey.
    write_image_u8(dir.file("a/compare.png"), 8, 4, 3, std::vector<std::uint8_t>(8 * 4 * 3, 255));
    write_contact_sheet(m, dir.file("sheet.png"), 40);
    const ImageF32 sheet = read_image_f32(dir.file("sheet.png"));
    // Cells of 40 x (20 label + 20 tile) with 4-pixel gaps.
    REQUIRE(sheet.width == 2 * 40 + 3 * 4);
    REQUIRE(sheet.height == 2 * 40 + 3 * 4);
    const int left = 4 + 20, right = 4 + 40 + 4 + 20, top = 4 + 20 + 10, bottom = 4 + 40 + 4 + 20 + 10;
    CHECK(sheet.at(left, top, 0) == Approx(1.0f));      // a's white compare.png
    CHECK(sheet.at(right, top, 0) < 0.5f);              // b: none, grey
    CHECK(sheet.at(left, bottom, 0) == Approx(sheet.at(right, top, 0)));  // c: none either
}
