// hbfriction benchmarks and tests: the time integrator's options for two periods from a given
// state (an exact orbit's), the second one recorded: the integrator's own view of that orbit,
// whose difference to it falls with the integrator's step.
#pragma once

#include <vector>

#include "hbf/time_integration.hpp"

namespace hbf::bench {

inline TimeIntegrationOptions two_periods_from_state(int samples, const std::vector<Output>& outputs) {
    TimeIntegrationOptions o;
    o.samples_per_period = samples;
    o.min_periods = 1;
    o.max_periods = 1;
    o.steady_tolerance = 1e-2;  // the first period "converges": the second is recorded
    o.shooting = false;
    o.stick_restart = false;
    o.max_events_per_period = 1000000;
    o.outputs = outputs;
    return o;
}

}  // namespace hbf::bench
