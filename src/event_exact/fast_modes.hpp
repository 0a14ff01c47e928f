// hbfriction — internal to event_exact: the fast modes of a contact pattern. Its eigenvalues far
// above the forcing's (beyond a gap above 4 w) are split off by their spectral projector, so
// that the engine flows them in closed form and steps with the slow ones (engine.hpp).
#pragma once

#include <Eigen/Dense>

#include "event_exact/engine.hpp"

namespace hbf::detail::exact {

/// Fills m.fast, m.a_slow, m.slow_basis, m.slow_coordinates and m.slow_restrict from m.a (n x n,
/// its last 3 states cos, sin, 1 of the forcing; nz = n - 3 dynamic states, the first 2 dofs of
/// them displacements and velocities) and sets slow_radius to the largest slow |eigenvalue|
/// (at least omega). Returns false (no split: m untouched but slow_radius, the largest
/// |eigenvalue|) when no eigenvalue is fast, an eigen-solve fails or its vectors do not pass
/// the residual checks. The eigen-decomposition of the dynamic block (omega-independent) is
/// cached per thread across frequencies.
bool split_fast_modes(const Eigen::MatrixXd& a, int nz, int dofs, double omega, ModeData& m, double& slow_radius);

}  // namespace hbf::detail::exact
