// hbf command line — a one-line progress display on a terminal's standard error.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace hbf::cli {

/// "hbf <command>: <text> <elapsed> s" on standard error while a long computation runs: on a
/// terminal one line redrawn at most 4 times a second and erased when done; otherwise (a log
/// file, a pipe: a batch run) one line a minute, kept, so that a run of an hour is not silent
/// (the first after a minute: a short run writes none). Nothing with --quiet.
class ProgressLine {
public:
    enum class Mode { off, terminal, log };
    /// `sink` and `interval` (the log mode's) are for the tests.
    ProgressLine(Mode mode, std::string command, std::FILE* sink = stderr,
                 std::chrono::steady_clock::duration interval = std::chrono::seconds(60))
        : mode_(mode), command_(std::move(command)), sink_(sink), interval_(interval),
          start_(std::chrono::steady_clock::now()), last_(start_) {}
    ~ProgressLine() { clear(); }
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;
    /// `force`: draw even within the 1/4 s (the last update; on a terminal only).
    void update(const std::string& text, bool force = false) {
        if (mode_ == Mode::off) return;
        const auto now = std::chrono::steady_clock::now();
        const double seconds = std::chrono::duration<double>(now - start_).count();
        if (mode_ == Mode::log) {
            if (now - last_ < interval_) return;
            last_ = now;
            std::fprintf(sink_, "hbf %s: %s %8.1f s\n", command_.c_str(), text.c_str(), seconds);
            std::fflush(sink_);
            return;
        }
        if (shown_ && !force && now - last_ < std::chrono::milliseconds(250)) return;
        last_ = now;
        shown_ = true;
        std::fprintf(sink_, "\rhbf %s: %s %8.1f s", command_.c_str(), text.c_str(), seconds);
        std::fflush(sink_);
    }
    void clear() {
        if (!shown_) return;
        std::fprintf(sink_, "\r\033[K");
        std::fflush(sink_);
        shown_ = false;
    }

private:
    Mode mode_;
    std::string command_;
    std::FILE* sink_;
    std::chrono::steady_clock::duration interval_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace hbf::cli
