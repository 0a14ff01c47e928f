// hbfriction — internal: time integration of models with massless DOFs, on their static
// condensation (model/massless.hpp): the options of the reduced model and its response
// expanded back to the original DOFs (time_integration.hpp).
#pragma once

#include "hbf/time_integration.hpp"
#include "model/massless.hpp"

namespace hbf::detail {

/// Options for the reduced system: the outputs that involve massive DOFs only, mapped.
TimeIntegrationOptions reduced_options(const MasslessCondensation& condensation, const TimeIntegrationOptions& options);

/// The reduced system's response as the original's: every DOF, the state and the
/// outputs of `options`. Massless DOFs come from the samples of the final period (their
/// y_max is the largest sample, their velocity a central difference of the samples; their
/// first harmonic uses the exact ones of the massive DOFs and the sampled friction force).
void expand(const MasslessCondensation& condensation, PeriodicResponse& response, const TimeIntegrationOptions& options);

}  // namespace hbf::detail
