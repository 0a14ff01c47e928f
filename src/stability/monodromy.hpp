// hbfriction — internal to stability: the monodromy matrix of the variational equation by
// CVODE (BDF, dense, exact Jacobian).
#pragma once

#include <Eigen/Dense>
#include <string>

#include "stability/variational.hpp"

namespace hbf::detail {

/// Phi(T) of ds' = A(t) ds of `v` by CVODE (relative tolerance `tolerance`, absolute 1e-2 of
/// it). False (and `failure`) when CVODE failed.
bool integrate_monodromy(const Variational& v, double tolerance, Eigen::MatrixXd& phi, std::string& failure);

}  // namespace hbf::detail
