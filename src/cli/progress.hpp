// hbf command line — a one-line progress display on a terminal's standard error.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace hbf::cli {

/// "hbf <command>: <text> <elapsed> s", redrawn at most 4 times a second, erased when done;
/// nothing unless enabled (a terminal, no --quiet).
class ProgressLine {
public:
    ProgressLine(bool enabled, std::string command)
        : enabled_(enabled), command_(std::move(command)), start_(std::chrono::steady_clock::now()) {}
    ~ProgressLine() { clear(); }
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;
    /// `force`: draw even within the 1/4 s (the last update).
    void update(const std::string& text, bool force = false) {
        if (!enabled_) return;
        const auto now = std::chrono::steady_clock::now();
        if (shown_ && !force && now - last_ < std::chrono::milliseconds(250)) return;
        last_ = now;
        shown_ = true;
        const double seconds = std::chrono::duration<double>(now - start_).count();
        std::fprintf(stderr, "\rhbf %s: %s %8.1f s", command_.c_str(), text.c_str(), seconds);
        std::fflush(stderr);
    }
    void clear() {
        if (!shown_) return;
        std::fprintf(stderr, "\r\033[K");
        std::fflush(stderr);
        shown_ = false;
    }

private:
    bool enabled_;
    std::string command_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace hbf::cli
