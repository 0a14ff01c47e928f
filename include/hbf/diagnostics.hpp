// hbfriction — what the libraries under it report. Ceres logs through glog, which by default
// prints every warning to standard error (hundreds of lines for one hard branch) and may write
// log files; CVODE calls an error handler. Neither is a result: hbfriction counts these
// messages and keeps the first, per computation (a MessageCollector on the computing thread),
// and the computation's verdict reports them (verdict.hpp; the hbf command: one warning line
// and exit code 3, see its --help). There is no process-wide store: computations on threads
// each count their own.
#pragma once

#include <string>

namespace hbf {

struct LibraryMessages {
    long long count = 0;  ///< warnings and errors reported by Ceres (glog) and CVODE
    std::string first;    ///< the first of them, prefixed by its source ("ceres: ...")
    /// Of them, Ceres' failed linear solves of a trial step ("Linear solver failure"): the
    /// Levenberg-Marquardt strategy retries such a step with more damping, so they never make
    /// an accepted point (whose residual is checked against the tolerance) doubtful.
    long long step_failures = 0;
    /// Adds `other`'s count; keeps this one's first message, else other's.
    void add(const LibraryMessages& other);
};

/// Routes glog's output (Ceres) into the collectors: from then on it prints nothing and writes
/// no log file. Process-wide and idempotent; the hbf command and the Python module call it at
/// start. An application that initialised glog itself keeps its own destinations; only the
/// counting sink is added.
void capture_library_messages();

namespace detail {
void record_library_message(const std::string& source, const std::string& text);
}  // namespace detail

/// Collects the messages the numerical libraries report on this thread while it lives (Ceres
/// runs single-threaded here and CVODE on the caller's thread, so a computation's messages are
/// those of its thread). Collectors nest: the innermost collects, and hands what it collected
/// to the enclosing one when it ends. A message raised on a thread without a collector is not
/// counted anywhere. Not copyable; create and destroy it on the same thread.
class MessageCollector {
public:
    MessageCollector();
    ~MessageCollector();
    MessageCollector(const MessageCollector&) = delete;
    MessageCollector& operator=(const MessageCollector&) = delete;
    /// What was collected so far.
    const LibraryMessages& messages() const { return messages_; }

private:
    friend void detail::record_library_message(const std::string&, const std::string&);
    LibraryMessages messages_;
    MessageCollector* enclosing_;
};

namespace detail {
/// Counts one message (source: "ceres", "cvode") in this thread's innermost collector.
void record_library_message(const std::string& source, const std::string& text);
}  // namespace detail

}  // namespace hbf
