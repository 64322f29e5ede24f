#include "jade/core/timing.h"

#include <cmath>
#include <cstdio>
#include <sys/resource.h>

namespace jade {

std::size_t peak_rss_bytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return std::size_t(usage.ru_maxrss) * 1024;  // Linux reports kilobytes
}

std::string format_megabytes(double bytes) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f MB", bytes / 1e6);
    return buf;
}

std::string format_relative_error(double error) {
    if (!std::isfinite(error)) return "none (below 2 samples per pixel, or no pixel shows the object)";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", error);
    return buf;
}

}  // namespace jade
