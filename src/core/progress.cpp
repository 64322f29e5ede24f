#include "jade/core/progress.h"

#include <cstdio>
#include <unistd.h>

namespace jade {

using Clock = std::chrono::steady_clock;

Progress::Progress(std::string label, std::size_t total, double time_budget_seconds)
    : label_(std::move(label)), total_(total ? total : 1), time_budget_(time_budget_seconds), start_(Clock::now()),
      last_draw_(start_), tty_(::isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() { finish(); }

void Progress::advance(std::size_t n) {
    const std::size_t done = done_.fetch_add(n) + n;
    const auto now = Clock::now();
    if (now - start_ < std::chrono::seconds(1)) return;
    const auto period = tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(5000);
    std::unique_lock<std::mutex> lock(draw_mutex_, std::try_to_lock);
    if (!lock.owns_lock() || finished_ || now - last_draw_ < period) return;
    last_draw_ = now;
    draw(done);
}

void Progress::finish() {
    std::lock_guard<std::mutex> lock(draw_mutex_);
    if (finished_) return;
    finished_ = true;
    if (drawn_ && tty_) std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
}

void Progress::draw(std::size_t done) {
    const double secs = std::chrono::duration<double>(Clock::now() - start_).count();
    // Work ends at its total or at its time budget, whichever comes first.
    double frac = std::min(1.0, double(done) / double(total_));
    if (time_budget_ > 0.0) frac = std::max(frac, std::min(1.0, secs / time_budget_));
    const double eta = frac > 0 ? secs * (1.0 - frac) / frac : 0.0;
    if (tty_) {
        constexpr int width = 30;
        const int filled = int(frac * width);
        std::string bar(filled, '#');
        bar.resize(width, '.');
        std::fprintf(stderr, "\r\033[K%s [%s] %3.0f%%  %.1fs, ~%.0fs left", label_.c_str(),
                     bar.c_str(), 100.0 * frac, secs, eta);
    } else {
        std::fprintf(stderr, "%s: %.0f%% after %.1fs, ~%.0fs left\n", label_.c_str(),
                     100.0 * frac, secs, eta);
    }
    std::fflush(stderr);
    drawn_ = true;
}

}  // namespace jade
