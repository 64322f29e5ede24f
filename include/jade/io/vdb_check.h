#pragma once
// A .vdb's header, then its grids, read in a process of its own before
// jaderender reads them (read_material_vdb, read_medium_vdb): OpenVDB
// allocates whatever a damaged length field asks and can crash on damaged
// data, and there that costs only the checking process
// (docs/robustness.md). The process is the small program jaderender-vdb-check,
// built beside jaderender; it links OpenVDB alone, so that it starts in
// 60–75 ms (most of it the dynamic linker resolving libopenvdb's symbols).

#include <cstdint>
#include <string>

namespace jade {

enum class VdbCheck { Header, Grids };

constexpr const char* kVdbCheckProgram = "jaderender-vdb-check";

// The word naming `part` on the program's command line: "header" or "grids".
const char* to_string(VdbCheck part);

// The body of jaderender-vdb-check: caps this process's address space at its
// present size plus `budget_bytes` and its CPU time at `cpu_seconds`, reads
// `part` of the file with OpenVDB, and returns the exit code: 0 read; 1
// OpenVDB refused it (its message, one line, on standard output); 2 it asked
// for more memory than the budget. A crash or the CPU limit ends the process
// by a signal.
int run_vdb_check(VdbCheck part, const std::string& path, std::uint64_t budget_bytes, int cpu_seconds);

}  // namespace jade
