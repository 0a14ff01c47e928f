// hbf command line — a long run asked to stop: by an interrupt (SIGINT, SIGTERM, SIGHUP) or by
// its time limit, so that it writes what it has computed (status stopped, exit 3) instead of
// nothing; and a watch on a continuation that crawls for minutes.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace hbf::cli {

/// --time-limit's value in seconds: 0 (none) .. 1e9; UsageError naming the flag and the range.
double parse_time_limit(const std::string& text);

/// While it lives, the first SIGINT, SIGTERM or SIGHUP is caught (a line on standard error says
/// the run stops and writes what it has); the second is the signal's default action (the
/// process ends, nothing written). A signal the process ignores (nohup's SIGHUP) stays ignored.
/// Its handlers are restored when it is destroyed. One at a time.
class StopRequest {
public:
    /// time_limit: seconds from construction (0: none).
    StopRequest(std::string command, double time_limit);
    ~StopRequest();
    StopRequest(const StopRequest&) = delete;
    StopRequest& operator=(const StopRequest&) = delete;
    /// "" while the run may go on; else why it stops ("interrupted (SIGINT)", "the time limit of
    /// 60 s (--time-limit) is reached").
    std::string why() const;
    /// ContinuationOptions::stop: why(), and the crawl watch (below) at each call.
    std::function<std::string()> function();
    /// Reported by the progress callback: the continuation's latest frequency.
    void reached(double omega);
    /// The crawl watch: where over `window` seconds the frequency moved by less than `share` of
    /// `range`, a warning on standard error (once per crawl) and a line for the verdict.
    void watch_crawl(double range, double share = 1e-3, double window = 120.0);
    /// The run works elsewhere (locating folds, the polish, stability): no crawl until the
    /// continuation reports a frequency again (its window restarts there).
    void pause_crawl();
    /// The crawls seen, one sentence each (for the verdict's notes).
    const std::vector<std::string>& crawls() const { return crawls_; }

private:
    void check_crawl();
    std::string command_;
    double time_limit_;
    std::chrono::steady_clock::time_point start_;
    double range_ = 0.0, share_ = 0.0, window_ = 0.0;
    bool has_omega_ = false, crawling_ = false;
    double omega_ = 0.0, mark_omega_ = 0.0;
    std::chrono::steady_clock::time_point mark_;
    std::vector<std::string> crawls_;
};

}  // namespace hbf::cli
