// hbfriction — internal to continuation: the location of folds and stick-slip transitions
// between the points of a traced branch (locate.cpp); continue_branch (continuation.cpp) calls them.
#pragma once

#include <functional>

#include "hbf/continuation.hpp"

namespace hbf::detail {

/// Inserts the transition points between successive points of each branch (see
/// continue_branch). Transitions that cannot be located are reported in the message. A
/// non-empty stop() ends the location (stop_location): the branch's points are kept.
void insert_transitions(HarmonicBalance& hb, Corrector& corrector, const CorrectorOptions& options,
                        double omega_scale, BranchResult& result, const std::function<std::string()>& stop = {});

/// Replaces each fold marked during the continuation (the point after the tangent's
/// omega-component changed sign) by the located fold inserted before it (locate_fold); a
/// sign change that is not a real turn in omega is unmarked. Counts in `result`. A non-empty
/// stop() ends the location (stop_location): the folds not yet located are unmarked.
void insert_folds(HarmonicBalance& hb, Corrector& corrector, const CorrectorOptions& options, double omega_scale,
                  BranchResult& result, const std::function<void(int done, int total)>& progress = {},
                  const std::function<std::string()>& stop = {});

/// Whether `stop` asks to stop (once asked, `why` is kept and the answer stays yes); the first
/// time, the result's status becomes stopped (unless worse) and the message says what was left.
bool stop_location(const std::function<std::string()>& stop, std::string& why, BranchResult& result,
                   const std::string& left);

}  // namespace hbf::detail
