#pragma once
// Measuring a run: wall time of stages and the process's peak memory, for
// summaries and benchmarks.

#include <chrono>
#include <cstddef>
#include <string>

namespace jade {

class Stopwatch {
public:
    Stopwatch() : start_(std::chrono::steady_clock::now()) {}
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    std::chrono::steady_clock::time_point start_;
};

// Peak resident memory of this process so far, in bytes (getrusage).
std::size_t peak_rss_bytes();

// "340.6 MB"
std::string format_megabytes(double bytes);

// An estimated relative error as printed: "0.0617", or what stands for it
// when the film cannot estimate one (render/film.h: below 2 samples per
// pixel, or no pixel shows the object).
std::string format_relative_error(double error);

}  // namespace jade
