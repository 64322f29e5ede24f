#include "jade/io/vdb_check.h"

#include "jade/core/error.h"

#include <openvdb/openvdb.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

namespace jade {

namespace {

// This process's address space, in bytes (/proc/self/statm; 0 if unknown).
std::uint64_t address_space_bytes() {
    std::ifstream in("/proc/self/statm");
    std::uint64_t pages = 0;
    in >> pages;
    return pages * std::uint64_t(::sysconf(_SC_PAGESIZE));
}

}  // namespace

const char* to_string(VdbCheck part) { return part == VdbCheck::Header ? "header" : "grids"; }

int run_vdb_check(VdbCheck part, const std::string& path, std::uint64_t budget_bytes, int cpu_seconds) {
    openvdb::initialize();
    const rlim_t cap = rlim_t(address_space_bytes() + budget_bytes);
    const rlimit memory{cap, cap};
    const rlimit cpu{rlim_t(cpu_seconds), rlim_t(cpu_seconds)};
    ::setrlimit(RLIMIT_AS, &memory);
    ::setrlimit(RLIMIT_CPU, &cpu);
    try {
        openvdb::io::File file(path);
        file.open(false);  // no memory mapping: mapped pages would count against the budget
        if (part == VdbCheck::Header) {
            file.getMetadata();
            file.readAllGridMetadata();
        } else {
            file.getGrids();
        }
        file.close();
    } catch (const std::bad_alloc&) {
        return 2;
    } catch (const std::exception& e) {
        std::fputs(one_line(e.what()).c_str(), stdout);
        return 1;
    }
    return 0;
}

}  // namespace jade
