// hbfriction — what the libraries under it report. Ceres logs through glog, which by default
// prints every warning to standard error (hundreds of lines for one hard branch) and may write
// log files; CVODE calls an error handler. Neither is a result: hbfriction counts these
// messages and keeps the first, and the caller summarises them (the hbf command: one warning
// line and exit code 3, see its --help).
#pragma once

#include <string>

namespace hbf {

struct LibraryMessages {
    long long count = 0;  ///< warnings and errors reported by Ceres (glog) and CVODE
    std::string first;    ///< the first of them, prefixed by its source ("ceres: ...")
};

/// Routes glog's output (Ceres) into the counters: from then on it prints nothing and writes no
/// log file. Process-wide and idempotent; the hbf command calls it at start. An application
/// that initialised glog itself keeps its own destinations; only the counting sink is added.
void capture_library_messages();

/// The messages counted since the start or the last reset (thread-safe).
LibraryMessages library_messages();
void reset_library_messages();

namespace detail {
/// Counts one message (source: "ceres", "cvode"); keeps it if it is the first.
void record_library_message(const std::string& source, const std::string& text);
}  // namespace detail

}  // namespace hbf
