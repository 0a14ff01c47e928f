// hbfriction — the sweep of hbf timeint (and Python's timeint) over a list of frequencies.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "hbf/event_exact.hpp"
#include "hbf/model.hpp"
#include "hbf/time_integration.hpp"

namespace hbf {

/// The frequencies a sweep computed, in order, and why it ended early.
struct SteadySweep {
    std::vector<PeriodicResponse> responses;
    std::string stopped;  ///< why the sweep ended before its last frequency, "" where it did not
};

/// The periodic steady states of `system` at `omegas`, in the order given: the first from the
/// stuck linear state (linear_stuck_state), each next one from the previous one's final state;
/// by integrate_steady_state with `options`, or with `exact` by exact_steady_state with
/// exact_sweep_options and exact_sweep_start (options.max_periods its budget). `stop` (may be
/// empty) is asked before each frequency, `before(k)` called before frequency k (progress); a
/// response ended by a stop request (PeriodicResponse::stopped) is left out and ends the sweep,
/// as does a stop answered before a frequency: `stopped` says where and why.
SteadySweep sweep_steady_states(const System& system, const std::vector<double>& omegas,
                                const TimeIntegrationOptions& options, const ExactOptions* exact,
                                const std::function<std::string()>& stop,
                                const std::function<void(std::size_t)>& before = {});

}  // namespace hbf
