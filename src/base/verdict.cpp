// hbfriction — a result's verdict (verdict.hpp): errors, warnings and notes, the status and
// summary they give, and the hbf exit code.
#include "hbf/verdict.hpp"

namespace hbf {

void Verdict::add(const LibraryMessages& messages) {
    if (messages.count == 0) return;
    const std::string line = std::to_string(messages.count) +
                             " warning(s) from the numerical libraries (not printed); the first: " + messages.first;
    if (messages.count == messages.step_failures)  // retried by the corrector: no accepted point depends on them
        note(line + " (trial steps whose linear solve failed, retried with more damping: every accepted point "
                    "meets the tolerance)");
    else
        warning(line);
}

void Verdict::add(const Verdict& other) {
    errors.insert(errors.end(), other.errors.begin(), other.errors.end());
    warnings.insert(warnings.end(), other.warnings.begin(), other.warnings.end());
    notes.insert(notes.end(), other.notes.begin(), other.notes.end());
}

std::string Verdict::status() const {
    return !errors.empty() ? "failed" : !warnings.empty() ? "incomplete" : "completed";
}

int Verdict::exit_code() const {
    return !errors.empty() ? exit_failure : !warnings.empty() ? exit_incomplete : exit_success;
}

std::string Verdict::summary() const {
    const std::vector<std::string>& reasons = !errors.empty() ? errors : warnings;
    std::string line = status();
    if (!reasons.empty()) {
        line += ": " + reasons.front();
        if (reasons.size() > 1) line += " (and " + std::to_string(reasons.size() - 1) + " more)";
    }
    return line;
}

}  // namespace hbf
