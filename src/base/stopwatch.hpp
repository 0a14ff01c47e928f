// hbfriction — internal: a monotonic stopwatch for the work counters (benchmarks, summaries).
#pragma once

#include <chrono>
#include <ctime>

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

/// CPU seconds of the calling thread: unlike the wall clock, not inflated when the thread is
/// preempted (a loaded machine, more threads than cores). For decisions taken on a measured
/// cost, which must not flip with the machine's load.
class ThreadCpuStopwatch {
public:
    ThreadCpuStopwatch() : start_(now()) {}
    /// Seconds since construction or the previous lap, without restarting.
    double seconds() const { return now() - start_; }
    double lap() {
        const double t = now();
        const double seconds = t - start_;
        start_ = t;
        return seconds;
    }

private:
    static double now() {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
    }
    double start_;
};

}  // namespace hbf::detail
