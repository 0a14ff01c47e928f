// hbfriction — internal: the periodic-orbit solver of a system's contact laws, chosen in one place.
#pragma once

#include <Eigen/Dense>

#include "hbf/event_exact.hpp"
#include "hbf/model.hpp"

namespace hbf::detail {

/// The exact periodic orbit at omega from `start` by the solver of the system's contacts:
/// rigid_periodic_orbit (law unilateral), elastic_periodic_orbit (law elastic), else
/// exact_periodic_orbit (1D friction). Throws as they do.
ExactOrbit law_periodic_orbit(const System& system, double omega, const Eigen::VectorXd& start,
                              const ExactOptions& options);

}  // namespace hbf::detail
