// hbfriction — internal to continuation: the location of folds and stick-slip transitions
// between the points of a traced branch (locate.cpp); continue_branch (continuation.cpp) calls them.
#pragma once

#include <functional>

#include "hbf/continuation.hpp"

namespace hbf::detail {

/// Inserts the transition points between successive points of each branch (see
/// continue_branch). Transitions that cannot be located are reported in the message.
void insert_transitions(HarmonicBalance& hb, Corrector& corrector, const CorrectorOptions& options,
                        double omega_scale, BranchResult& result);

/// Replaces each fold marked during the continuation (the point after the tangent's
/// omega-component changed sign) by the located fold inserted before it (locate_fold); a
/// sign change that is not a real turn in omega is unmarked. Counts in `result`.
void insert_folds(HarmonicBalance& hb, Corrector& corrector, const CorrectorOptions& options, double omega_scale,
                  BranchResult& result, const std::function<void(int done, int total)>& progress = {});

}  // namespace hbf::detail
