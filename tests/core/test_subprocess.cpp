// run_program: what a program wrote, how it ended, and a program that is not
// there, told apart (jade/core/subprocess.h).

#include "jade/core/subprocess.h"

#include <catch2/catch.hpp>

#include <csignal>
#include <filesystem>

using namespace jade;

TEST_CASE("run_program: its output, its exit code, the signal that ended it, or that it never started",
          "[subprocess]") {
    const ProcessResult said = run_program("/bin/sh", {"-c", "printf 'two\\nlines'; echo lost >&2; exit 3"});
    CHECK(said.started);
    CHECK(said.output == "two\nlines");  // standard error is not captured
    CHECK(said.exit_code == 3);
    CHECK(said.signal == 0);

    const ProcessResult crashed = run_program("/bin/sh", {"-c", "kill -SEGV $$"});
    CHECK(crashed.started);
    CHECK(crashed.exit_code == -1);
    CHECK(crashed.signal == SIGSEGV);

    // Standard input is /dev/null: a program that reads it ends at once.
    const ProcessResult reader = run_program("/bin/sh", {"-c", "cat; echo done"});
    CHECK(reader.output == "done\n");

    CHECK_FALSE(run_program("/nonexistent/program", {}).started);
}

TEST_CASE("own_executable_dir is the directory of the running test binary", "[subprocess]") {
    const std::string dir = own_executable_dir();
    REQUIRE_FALSE(dir.empty());
    CHECK(std::filesystem::is_directory(dir));
    CHECK(std::filesystem::exists(std::filesystem::path(dir) / "jade_unit_tests"));
}
