// hbfriction — internal to event_exact: what the solver takes (systems, states); the options,
// the refusals and the cost bound of event_exact.hpp are in validation.cpp.
#pragma once

#include <Eigen/Dense>
#include <memory>

#include "hbf/model.hpp"
#include "model/massless.hpp"

namespace hbf::detail::exact {

/// Throws InvalidInput naming why the exact solver cannot take `system` at omega. Returns the
/// static condensation of its massless DOFs, null when M > 0 (none is needed).
std::unique_ptr<detail::MasslessCondensation> validate_system(const System& system, double omega);

/// Throws InvalidInput unless `state` has the size of `system`'s (2 N + 2 n_c).
void check_state_size(const System& system, const Eigen::VectorXd& state);

}  // namespace hbf::detail::exact
