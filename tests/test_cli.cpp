// The jaderender binary run as a user runs it: a working command, and each
// kind of bad input -> exit code 2, one line on stderr naming the problem,
// and no output file left behind.

#include "jade/image_io.h"

#include "test_util.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <sys/wait.h>

using jade_test::TempDir;

namespace {

struct Result {
    int code = -1;
    std::string out, err;
};

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

Result run(const TempDir& dir, const std::string& args) {
    const std::string cmd = std::string(JADE_BINARY) + " " + args + " >" + dir.file("stdout.txt") +
                            " 2>" + dir.file("stderr.txt") + " </dev/null";
    const int status = std::system(cmd.c_str());
    Result r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir.file("stdout.txt"));
    r.err = slurp(dir.file("stderr.txt"));
    std::filesystem::remove(dir.file("stdout.txt"));
    std::filesystem::remove(dir.file("stderr.txt"));
    return r;
}

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

void require_clean_failure(const TempDir& dir, const std::string& args, const std::string& names) {
    INFO("jaderender " << args);
    const Result r = run(dir, args);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK_THAT(r.err, Catch::Contains(names));
    CHECK_FALSE(std::filesystem::exists(dir.file("out.vdb")));
    // Nothing else either: no temporary file left in the output folder.
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        CHECK_THAT(e.path().filename().string(), !Catch::Contains("partial"));
}

}  // namespace

TEST_CASE("volume: the demo photo gives a .vdb and a one-line summary", "[cli]") {
    TempDir dir;
    const Result r = run(dir, "volume --photo " JADE_DATA_DIR
                              "/photos/ambientcg_Onyx002_512_diff.jpg --resolution 32 --out " +
                                  dir.file("out.vdb") + " --preview " + dir.file("slice.png"));
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(std::filesystem::file_size(dir.file("out.vdb")) > 32u * 32u * 32u);
    CHECK(std::filesystem::exists(dir.file("slice.png")));
    CHECK(lines(r.out) == 1);
    CHECK_THAT(r.out, Catch::Contains("32^3") && Catch::Contains("MB"));
    CHECK(dir.entries() == 2);
}

TEST_CASE("--help documents the flags and exits 0", "[cli]") {
    TempDir dir;
    const Result r = run(dir, "volume --help");
    CHECK(r.code == 0);
    for (const char* flag : {"--photo", "--mask", "--resolution", "--octaves", "--k", "--seed",
                             "--match", "--ds", "--da", "--out"})
        CHECK_THAT(r.out, Catch::Contains(flag));
}

TEST_CASE("bad input: exit 2, one line naming the problem, no output", "[cli]") {
    TempDir dir;
    const std::string out = " --out " + dir.file("out.vdb");
    const std::string demo = JADE_DATA_DIR "/photos/ambientcg_Onyx002_512_diff.jpg";

    require_clean_failure(dir, "volume --photo " + dir.file("missing.png") + out, "missing.png");

    std::ofstream(dir.file("corrupt.png"), std::ios::binary) << "\x89PNG\r\n\x1a\ngarbage";
    require_clean_failure(dir, "volume --photo " + dir.file("corrupt.png") + out, "corrupt.png");

    jade::write_image_u8(dir.file("clear.png"), 2, 2, 4,
                         {9, 9, 9, 0, 9, 9, 9, 0, 9, 9, 9, 0, 9, 9, 9, 0});
    require_clean_failure(dir, "volume --photo " + dir.file("clear.png") + out, "no foreground");

    jade::write_image_u8(dir.file("mask.png"), 3, 3, 1, std::vector<std::uint8_t>(9, 255));
    require_clean_failure(dir, "volume --photo " + demo + " --mask " + dir.file("mask.png") + out,
                          "mask.png");

    require_clean_failure(dir, "volume --photo " + demo + " --k 2" + out, "--k");
    require_clean_failure(dir, "volume --photo " + demo + " --resolution abc" + out, "--resolution");
    require_clean_failure(dir, "volume --photo " + demo + " --match both" + out, "--match");
    require_clean_failure(dir, "volume --photo " + demo + " --out " + dir.file("no/such/dir/v.vdb"),
                          "does not exist");
}
