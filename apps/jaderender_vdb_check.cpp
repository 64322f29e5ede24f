// jaderender-vdb-check: reads one part of a .vdb with OpenVDB under a memory
// and CPU budget, in a process of its own, for jaderender's .vdb reader
// (jade/io/vdb_check.h). It parses its arguments and calls the library.
//
//   jaderender-vdb-check header|grids FILE BUDGET_BYTES CPU_SECONDS

#include "jade/io/vdb_check.h"

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
    if (argc != 5 || (std::string(argv[1]) != "header" && std::string(argv[1]) != "grids")) {
        std::fprintf(stderr, "usage: %s header|grids FILE BUDGET_BYTES CPU_SECONDS\n", argv[0]);
        return 3;
    }
    const jade::VdbCheck part = std::string(argv[1]) == "header" ? jade::VdbCheck::Header : jade::VdbCheck::Grids;
    return jade::run_vdb_check(part, argv[2], std::strtoull(argv[3], nullptr, 10), std::atoi(argv[4]));
}
