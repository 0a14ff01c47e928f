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

class Engine;
/// The cost of one period of e's flows in Taylor steps: T / step plus the fast modes' samples /
/// 16, the larger of the all-stuck and all-slipping patterns (exact_steps_per_period).
double period_cost(Engine& e);

/// Throws InvalidInput unless `state` has the size of `system`'s (2 N + 2 n_c).
void check_state_size(const System& system, const Eigen::VectorXd& state);

}  // namespace hbf::detail::exact
