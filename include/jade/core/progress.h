#pragma once
// Progress of long work, reported on stderr. The library never prints by
// itself: a function that may take more than a second takes a Progress* (null
// = silent) and advances it from any thread. Nothing is shown during the first
// second, so quick runs stay quiet; on a terminal a bar is redrawn in place,
// otherwise (CI logs, pipes) one line is written every few seconds.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace jade {

class Progress {
public:
    // time_budget_seconds > 0: the work also ends then (a render's --time),
    // so the bar and its estimate follow whichever end comes first.
    Progress(std::string label, std::size_t total, double time_budget_seconds = 0.0);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    // Thread-safe; cheap enough to call once per slice or tile.
    void advance(std::size_t n = 1);
    // Clears the bar (if one was drawn). Called by the destructor too.
    void finish();

private:
    void draw(std::size_t done);

    std::string label_;
    std::size_t total_;
    double time_budget_ = 0.0;
    std::atomic<std::size_t> done_{0};
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_draw_;
    std::mutex draw_mutex_;
    bool tty_;
    bool drawn_ = false;
    bool finished_ = false;
};

}  // namespace jade
