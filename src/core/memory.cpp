#include "jade/core/memory.h"

#include "jade/core/error.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace jade {

namespace {
// A number from the first line of a file ("max" or unreadable: 0).
std::uint64_t number_in(const std::string& path) {
    std::ifstream in(path);
    std::string word;
    if (!(in >> word) || word == "max") return 0;
    try {
        return std::stoull(word);
    } catch (const std::exception&) {
        return 0;
    }
}

std::uint64_t mem_available() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    std::uint64_t kb = 0;
    std::string unit;
    while (in >> key >> kb >> unit)
        if (key == "MemAvailable:") return kb * 1024;
    return 0;
}

std::string gigabytes(std::uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / 1e9);
    return text;
}
}  // namespace

std::uint64_t available_memory_bytes() {
    std::uint64_t available = mem_available();
    // cgroup v2: the limit and the use of this process's group.
    const std::uint64_t limit = number_in("/sys/fs/cgroup/memory.max");
    if (limit > 0) {
        const std::uint64_t used = number_in("/sys/fs/cgroup/memory.current");
        const std::uint64_t room = limit > used ? limit - used : 0;
        available = available > 0 ? std::min(available, room) : room;
    }
    return available;
}

void require_memory(std::uint64_t bytes, const std::string& what) {
    const std::uint64_t available = available_memory_bytes();
    if (available > 0 && bytes > available)
        throw Error(what + " needs about " + gigabytes(bytes) + " of memory; " + gigabytes(available) +
                    " are available");
}

}  // namespace jade
