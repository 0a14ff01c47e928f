// hbfriction — internal: a monotonic stopwatch for the work counters (benchmarks, summaries).
#pragma once

#include <chrono>

namespace hbf::detail {

class Stopwatch {
public:
    Stopwatch() : start_(std::chrono::steady_clock::now()) {}
    /// Seconds since construction or the previous lap, and restarts.
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double seconds = std::chrono::duration<double>(now - start_).count();
        start_ = now;
        return seconds;
    }

private:
    std::chrono::steady_clock::time_point start_;
};

}  // namespace hbf::detail
