// The shipped Blender import (scripts/blender/jaderender_blender.py) against
// jaderender, in Debian's Blender and Cycles: the same job rendered by both
// agrees in mean colour per channel over the object's pixels
// (docs/blender.md). Each renderer renders twice with different seeds; the
// two images' per-pixel differences give each mean's standard error, whatever
// the renderer. The images are written side by side into the build folder.

#include "jade/io/image_io.h"

#include "support/test_util.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

using jade::ImageF32;
using jade::read_image_f32;
using jade_test::TempDir;

namespace {

const std::string kData = JADE_DATA_DIR;

int run(const std::string& cmd, const TempDir& dir) {
    const std::string full = cmd + " >" + dir.file("log.txt") + " 2>&1 </dev/null";
    const int status = std::system(full.c_str());
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code != 0) {
        std::ifstream in(dir.file("log.txt"));
        std::stringstream ss;
        ss << in.rdbuf();
        FAIL(cmd << " exited " << code << ":\n" << ss.str());
    }
    return code;
}

void jaderender(const std::string& args, const TempDir& dir) { run(std::string(JADE_BINARY) + " " + args, dir); }

void blender(const std::string& job, const std::string& exr, unsigned seed, const TempDir& dir) {
    run("blender -b --factory-startup --python " + std::string(JADE_BLENDER_SCRIPT) + " -- " + job + " --exr " + exr +
            " --seed " + std::to_string(seed),
        dir);
}

// Per channel: the mean over the mask's pixels of the two renders' average,
// and its standard error from their per-pixel differences (two independent
// renders: Var(pixel mean) = E[(a - b)^2] / 4).
struct ChannelMeans {
    std::array<double, 3> mean{}, error{};
};

ChannelMeans masked_means(const ImageF32& a, const ImageF32& b, const ImageF32& mask) {
    ChannelMeans m;
    std::array<double, 3> diff2{};
    double n = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (mask.at(x, y, 3) < 0.5f) continue;
            n += 1.0;
            for (int c = 0; c < 3; ++c) {
                m.mean[c] += 0.5 * (a.at(x, y, c) + b.at(x, y, c));
                diff2[c] += (a.at(x, y, c) - b.at(x, y, c)) * double(a.at(x, y, c) - b.at(x, y, c));
            }
        }
    REQUIRE(n > 100.0);
    for (int c = 0; c < 3; ++c) {
        m.mean[c] /= n;
        m.error[c] = std::sqrt(diff2[c] / 4.0) / n;
    }
    return m;
}

std::string job_json(const std::string& mesh, const std::string& medium, const std::string& boundary,
                     const std::string& lights, int size, int spp) {
    return "{\"scene\": {\"mesh\": \"" + mesh + "\", \"boundary\": \"" + boundary + "\", \"ior\": 1.5},\n"
           " \"medium\": " + medium + ",\n"
           " \"camera\": CAMERA, \"lights\": " + lights + ",\n"
           " \"settings\": {\"spp\": " + std::to_string(spp) + ", \"seed\": 1},\n"
           " \"outputs\": {\"out\": \"ours.exr\", \"png\": \"\", \"convergence\": \"\", \"exposure\": 1.0}}\n";
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string replace(std::string s, const std::string& what, const std::string& with) {
    return s.replace(s.find(what), what.size(), with);
}

// Renders `job` with both renderers (two seeds each) and the object's
// coverage (jaderender, --transparent), writes ours | Cycles to `side_by_side`.
struct Comparison {
    ChannelMeans ours, cycles;
};

Comparison render_both(const TempDir& dir, const std::string& job, const std::string& side_by_side) {
    for (unsigned seed : {1u, 2u}) {
        jaderender("render --job " + job + " --seed " + std::to_string(seed) + " --out " +
                       dir.file("ours" + std::to_string(seed) + ".exr"),
                   dir);
        blender(job, dir.file("cycles" + std::to_string(seed) + ".exr"), seed, dir);
    }
    jaderender("render --job " + job + " --transparent --spp 16 --out " + dir.file("coverage.exr"), dir);
    const ImageF32 o1 = read_image_f32(dir.file("ours1.exr")), o2 = read_image_f32(dir.file("ours2.exr"));
    const ImageF32 c1 = read_image_f32(dir.file("cycles1.exr")), c2 = read_image_f32(dir.file("cycles2.exr"));
    const ImageF32 mask = read_image_f32(dir.file("coverage.exr"));
    REQUIRE(c1.width == o1.width);
    REQUIRE(c1.height == o1.height);
    run("oiiotool " + dir.file("ours1.exr") + " --ch R,G,B " + dir.file("cycles1.exr") +
            " --ch R,G,B --mosaic 2x1 --colorconvert linear sRGB -o " + side_by_side,
        dir);
    return {masked_means(o1, o2, mask), masked_means(c1, c2, mask)};
}

// The volume the pipeline wrote into dir/fit/ in the vase, index-matched under
// a constant sky of 1, rendered by both; each channel's means within `bound`.
void check_vase_volume(const TempDir& dir, const std::array<double, 3>& bound, const std::string& side_by_side) {
    const std::string job = dir.file("job.json");
    write(job, replace(job_json(kData + "/meshes/greek-vase-01.glb", "{\"volume\": \"fit/volume.vdb\"}", "none",
                                "{\"irradiance\": 0, \"environment\": \"1.0\"}", 64, 64),
                       "CAMERA",
                       "{\"origin\": [0, 0.5, 0.82], \"target\": [0, 0.2, 0], \"fov_degrees\": 40, "
                       "\"width\": 64, \"height\": 64}"));
    const Comparison r = render_both(dir, job, std::string(JADE_TEST_OUTPUT_DIR) + "/" + side_by_side);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": ours " << r.ours.mean[c] << " +- " << r.ours.error[c] << ", Cycles "
                        << r.cycles.mean[c] << " +- " << r.cycles.error[c]);
        CHECK(std::abs(r.cycles.mean[c] / r.ours.mean[c] - 1.0) <= bound[c]);
    }
}

}  // namespace

TEST_CASE("Blender round trip: a homogeneous medium in each boundary renders alike in Cycles", "[blender]") {
    // A sphere of radius 1 (optical radius 3, 1.5 and 0.8 by channel) under a
    // 20-degree sun and a grey sky, seen from 3.7 units: within the two
    // renders' combined noise (4 sigma) plus 0.5 %.
    for (const char* boundary : {"split", "fresnel", "none"}) {
        DYNAMIC_SECTION(boundary) {
            TempDir dir;
            const std::string job = dir.file("job.json");
            write(job, replace(job_json(kData + "/reference/unit_sphere.obj",
                                        "{\"sigma_s\": [3.0, 1.5, 0.8], \"sigma_a\": [0.05, 0.2, 0.4]}", boundary,
                                        "{\"direction\": [0.35, 0.8, 0.5], \"irradiance\": 3.0, "
                                        "\"radius_degrees\": 20, \"environment\": \"0.2\"}",
                                        40, 128),
                               "CAMERA",
                               "{\"origin\": [0, 0.8, 3.6], \"target\": [0, 0, 0], \"fov_degrees\": 40, "
                               "\"width\": 40, \"height\": 40}"));
            const Comparison r =
                render_both(dir, job, std::string(JADE_TEST_OUTPUT_DIR) + "/blender-homogeneous-" + boundary + ".png");
            for (int c = 0; c < 3; ++c) {
                INFO("channel " << c << ": ours " << r.ours.mean[c] << " +- " << r.ours.error[c] << ", Cycles "
                                << r.cycles.mean[c] << " +- " << r.cycles.error[c]);
                const double noise = std::hypot(r.ours.error[c], r.cycles.error[c]);
                CHECK(std::abs(r.cycles.mean[c] - r.ours.mean[c]) <= 4.0 * noise + 0.005 * r.ours.mean[c]);
            }
        }
    }
}

TEST_CASE("Blender round trip: a delta light behind the split boundary becomes a sun that lights the inside alike",
          "[blender]") {
    // Cycles cannot reach a delta light inside glass: the script stands a
    // 10-degree sun in for it, which glossy rays do not see (a delta light
    // has no highlight). The same sphere as above under jaderender's delta
    // light: within the renders' combined noise (4 sigma) plus 5 %, what the
    // disc itself changes (measured at 4096 spp each: Cycles +0.4 %, +0.9 %,
    // +3.8 %; the blue channel, the least extinct, sees the most of the
    // disc's spread of directions).
    TempDir dir;
    const std::string job = dir.file("job.json");
    write(job, replace(job_json(kData + "/reference/unit_sphere.obj",
                                "{\"sigma_s\": [3.0, 1.5, 0.8], \"sigma_a\": [0.05, 0.2, 0.4]}", "split",
                                "{\"direction\": [0.35, 0.45, 0.82], \"irradiance\": 3.0, "
                                "\"radius_degrees\": 0, \"environment\": \"0.2\"}",
                                40, 128),
                       "CAMERA",
                       "{\"origin\": [0, 0.8, 3.6], \"target\": [0, 0, 0], \"fov_degrees\": 40, "
                       "\"width\": 40, \"height\": 40}"));
    const Comparison r = render_both(dir, job, std::string(JADE_TEST_OUTPUT_DIR) + "/blender-delta-light.png");
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": ours " << r.ours.mean[c] << " +- " << r.ours.error[c] << ", Cycles "
                        << r.cycles.mean[c] << " +- " << r.cycles.error[c]);
        const double noise = std::hypot(r.ours.error[c], r.cycles.error[c]);
        CHECK(std::abs(r.cycles.mean[c] - r.ours.mean[c]) <= 4.0 * noise + 0.05 * r.ours.mean[c]);
    }
}

TEST_CASE("Blender round trip: a heterogeneous volume in the vase, index-matched and lit by the sky", "[blender]") {
    // The demo photo's volume at 64^3 with the contrast a fit gives it
    // (1, 4, 9.5) and k_s = 0, masked to the vase by the pipeline (--fit none
    // keeps it). Cycles reads the .vdb's sigma grids cut at
    // surface_distance < 0. Measured: Cycles 1.6 %, 2.9 % and 3.8 % darker
    // (noise 0.3 %); the bound is 5 %. A constant grid agrees within 1.3 %,
    // so the rest comes with the heterogeneity. With a fit's k_s (0.07..2.3)
    // Cycles differs more, up to 13 % brighter in blue: the next test.
    TempDir dir;
    jaderender("volume --photo " + kData + "/photos/ambientcg_Onyx002_512_diff.jpg --resolution 64 --contrast 1,4,9.5 "
               "--out " + dir.file("v.vdb"),
               dir);
    jaderender("--photo " + kData + "/photos/ambientcg_Onyx002_512_diff.jpg --mesh " + kData +
                   "/meshes/greek-vase-01.glb --volume " + dir.file("v.vdb") +
                   " --fit none --spp 4 --width 32 --height 32 --out " + dir.file("fit"),
               dir);
    check_vase_volume(dir, {0.05, 0.05, 0.05}, "blender-volume.png");
}

TEST_CASE("Blender round trip: the demo's fitted volume in the vase, index-matched and lit by the sky", "[blender]") {
    // The demo fit's k_s (2.30, 0.92, 0.07) and contrast (1.7, 6.1, 11.2) at
    // 64^3, in the scene above. Cycles is 3 % darker in red, 1.4 % brighter
    // in green and 12.5 % brighter in blue. The third witness,
    // Mitsuba 3 (scripts/bench-witness.sh, docs/blender.md "A fitted
    // volume"), agrees with jaderender within 3.1 %, 0.7 % and 0.5 %, and
    // Cycles is as far off on the constant grid of the same mean (+12.9 % in
    // blue), so the difference is Cycles' (as the script drives it) on this
    // medium's coefficients (blue: albedo 0.47, 53 mean free paths per unit),
    // not the heterogeneity. Bounds: 5 % in red and green, 15 % in blue.
    // (The volume the photo gives has changed since with the structure
    // estimate; on 2026-12-01, at 64 spp, Cycles read −0.7 %, −1.3 % and
    // −2.2 % against jaderender, noise 0.2 %.)
    TempDir dir;
    jaderender("--photo " + kData + "/photos/ambientcg_Onyx002_512_diff.jpg --mesh " + kData +
                   "/meshes/greek-vase-01.glb --resolution 64 --ks 2.30,0.92,0.07 --contrast 1.7,6.1,11.2"
                   " --fit none --spp 4 --width 32 --height 32 --out " + dir.file("fit"),
               dir);
    check_vase_volume(dir, {0.05, 0.05, 0.15}, "blender-fitted-volume.png");
}
