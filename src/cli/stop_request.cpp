// hbf command line — StopRequest (stop_request.hpp): the caught interrupt, the time limit and the
// crawl watch.
#include "stop_request.hpp"

#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "arguments.hpp"
#include "hbf/error.hpp"

namespace hbf::cli {

namespace {
volatile std::sig_atomic_t caught = 0;
bool active = false;
constexpr int signals[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction previous[3];

extern "C" void on_signal(int signal) {
    caught = signal;
    // The next one takes its default action (async-signal-safe: sigaction, write).
    struct sigaction fallback {};
    fallback.sa_handler = SIG_DFL;
    sigemptyset(&fallback.sa_mask);
    for (int k = 0; k < 3; ++k)
        if (previous[k].sa_handler != SIG_IGN) sigaction(signals[k], &fallback, nullptr);
    static const char line[] =
        "\nhbf: interrupted: stopping, the points computed so far will be written (again to abort)\n";
    const ssize_t written = write(STDERR_FILENO, line, sizeof line - 1);
    (void)written;
}

const char* signal_name(int signal) {
    switch (signal) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        case SIGHUP: return "SIGHUP";
        default: return "a signal";
    }
}
}  // namespace

double parse_time_limit(const std::string& text) {
    const double seconds = parse_double("--time-limit", text);
    if (!(seconds >= 0.0 && seconds <= 1e9))
        throw UsageError("--time-limit = " + text + " is out of range: allowed 0 (none) .. 1e9 seconds");
    return seconds;
}

StopRequest::StopRequest(std::string command, double time_limit)
    : command_(std::move(command)), time_limit_(time_limit), start_(std::chrono::steady_clock::now()), mark_(start_) {
    if (active) throw std::logic_error("StopRequest: one at a time");
    active = true;
    caught = 0;
    struct sigaction handler {};
    handler.sa_handler = on_signal;
    sigemptyset(&handler.sa_mask);
    handler.sa_flags = SA_RESTART;
    for (int k = 0; k < 3; ++k) {
        sigaction(signals[k], nullptr, &previous[k]);
        // An ignored signal stays ignored (nohup's SIGHUP, SIGINT of a background job).
        if (previous[k].sa_handler != SIG_IGN) sigaction(signals[k], &handler, nullptr);
    }
}

StopRequest::~StopRequest() {
    for (int k = 0; k < 3; ++k) sigaction(signals[k], &previous[k], nullptr);
    active = false;
}

std::string StopRequest::why() const {
    if (caught != 0) return std::string("interrupted (") + signal_name(caught) + ")";
    if (time_limit_ > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() >= time_limit_)
        return "the time limit of " + format_number(time_limit_) + " s (--time-limit) is reached";
    return "";
}

std::function<std::string()> StopRequest::function() {
    return [this] {
        check_crawl();
        return why();
    };
}

void StopRequest::reached(double omega) {
    omega_ = omega;
    if (!has_omega_) {
        has_omega_ = true;
        mark_omega_ = omega;
        mark_ = std::chrono::steady_clock::now();
    }
}

void StopRequest::pause_crawl() {
    has_omega_ = false;
    crawling_ = false;
}

void StopRequest::watch_crawl(double range, double share, double window) {
    range_ = range;
    share_ = share;
    window_ = window;
}

void StopRequest::check_crawl() {
    if (!(window_ > 0.0) || !has_omega_) return;
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - mark_).count();
    if (seconds < window_) return;
    const double moved = std::abs(omega_ - mark_omega_);
    if (moved < share_ * range_) {
        if (!crawling_) {
            const std::string line = "the continuation has moved w by " + format_number(moved) + " in the last " +
                                     format_number(std::round(seconds)) + " s near w = " + format_number(omega_) +
                                     " (its step has collapsed: a corner or a fold resolved slowly); an interrupt "
                                     "(Ctrl-C) or --time-limit writes the points computed so far";
            std::cerr << "\nhbf " << command_ << ": warning: " << line << "\n";
            crawls_.push_back("the continuation crawled near w = " + format_number(omega_) + " (less than " +
                              format_number(share_) + " of the range in " + format_number(window_) + " s)");
        }
        crawling_ = true;
    } else {
        crawling_ = false;
    }
    mark_ = now;
    mark_omega_ = omega_;
}

}  // namespace hbf::cli
