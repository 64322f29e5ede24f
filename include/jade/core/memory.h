#pragma once
// Checking a run's memory before it starts: a volume or a film too large for
// the machine is refused in one line instead of failing with bad_alloc after
// minutes of work.

#include <cstdint>
#include <string>

namespace jade {

// The memory this process may still take: the smaller of the machine's
// MemAvailable (/proc/meminfo) and its cgroup's limit less its use (a
// container, a Slurm job). 0 when neither can be read.
std::uint64_t available_memory_bytes();

// Throws jade::Error "<what> needs about X GB of memory; Y GB are available"
// when `bytes` exceed what is available (nothing when that is unknown).
void require_memory(std::uint64_t bytes, const std::string& what);

}  // namespace jade
