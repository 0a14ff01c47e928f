// hbfriction — what a computed result is worth: the one verdict type of every result (an FRF,
// a time-integration sweep, a study) and the one mapping from verdict to the hbf command's
// exit code.
#pragma once

#include <string>
#include <vector>

#include "hbf/diagnostics.hpp"

namespace hbf {

/// Exit codes of every `hbf` command (documented in `hbf --help`).
/// 0: completed; 1: failed (what was computed is written); 2: bad input (nothing written);
/// 3: written, but incomplete or doubtful (each reason a warning on standard error).
enum ExitCode : int { exit_success = 0, exit_failure = 1, exit_bad_input = 2, exit_incomplete = 3 };

/// What makes a result failed (errors), incomplete or doubtful (warnings), or worth a remark
/// that does not change its status (notes). Each line is a sentence naming the point, the
/// value and what to do.
struct Verdict {
    std::vector<std::string> errors, warnings, notes;

    void error(const std::string& text) { errors.push_back(text); }
    void warning(const std::string& text) { warnings.push_back(text); }
    void note(const std::string& text) { notes.push_back(text); }
    /// A warning when the numerical libraries reported anything (their count and the first).
    void add(const LibraryMessages& messages);
    /// Appends another verdict's errors, warnings and notes.
    void add(const Verdict& other);

    /// "failed" with errors, else "incomplete" with warnings, else "completed".
    std::string status() const;
    /// The hbf command's exit code: exit_failure with errors, else exit_incomplete with
    /// warnings, else exit_success.
    int exit_code() const;
    /// One line: the status, then the first error or warning (and how many more).
    std::string summary() const;
};

}  // namespace hbf
