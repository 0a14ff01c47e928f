// hbfriction — internal: time integration of structures whose contacts are rigid unilateral
// contacts with Coulomb friction (law unilateral, src/contact/unilateral.cpp) on massless
// contact coordinates, the time-domain reference for their harmonic balance. Not installed.
//
// The DOFs split into those with mass (a row of M not zero), y_m, and the massless ones, y_c,
// which carry the contacts (every contact direction lies on massless DOFs), no damping and
// their stiffness K_cc regular:
//   M_mm y_m'' + C_mm y_m' + K_mm y_m + K_mc y_c = F_m(t)            (the structure)
//   K_cm y_m + K_cc y_c + W lambda = F_c(t)                          (the massless nodes)
// with F = F_exc cos(h w t) + F_static and, per contact, lambda = (lambda_T, lambda_N) under
// Signorini and Coulomb. Each time step t_k -> t_k+1 = t_k + dt:
//   * y_m by velocity Verlet (second order; the force on the masses is Lipschitz in y_m):
//     y_m+ = y_m + dt v + dt^2 a / 2, then (M + dt C / 2) v+ = M v + dt (M a + f+) / 2 and
//     a+ = M^-1 (f+ - C v+), f = F_m - K_mm y_m - K_mc y_c;
//   * the contacts at t_k+1, given y_m+: a complementarity problem in lambda, with the
//     relative displacements q = W^T y_c = q0 - G lambda (q0 those of the nodes without contact
//     forces, G = W^T K_cc^-1 W the Delassus matrix), Signorini on the normal displacement and
//     Coulomb on the tangential increment u - u_k over the step (stick holds u_k, a slip moves
//     u along the force: the implicit, backward-Euler Coulomb law), written as the projections
//       lambda_N = max(0, lambda_N + e_N (v - g_0)),
//       lambda_T = proj_{|.| <= mu lambda_N} (lambda_T + e_T (u - u_k)),
//     e = 1 / diag(G), and solved by the semi-smooth Newton method (exact generalised Jacobian,
//     halving steps), warm-started from the previous step, to 1e-12 of the forces' size.
// The step is the period over a multiple of samples_per_period: at least 16 of them, and at
// least 20 steps per period of the stiffest mode of M_mm, K_mm (the nodes held: an upper bound
// of the stiffest mode; Verlet is stable below 1/pi of it). One period at a time, until the
// Poincare map (y_m, v_m / w, the tangential displacements) changes by less than
// steady_tolerance.
//
// Metrics of the final period, on its steps: y_max (the samples, refined by a parabola), the
// first harmonics (the discrete Fourier sums), per contact the stick, slip and open times (the
// projections' branches), the normal force's mean and half range, the friction energy
// sum lambda_T,mid . (u_k+1 - u_k) (the normal force does no work but across a step that opens
// or closes: that residue enters the energy balance only); input and viscous energies by the
// same second-order sums. The energy balance holds to the scheme's O(dt^2).
//
// Refused up front (InvalidInput): a system mixing law unilateral with other laws, a contact
// direction on a DOF with mass, damping on a massless DOF, M_mm not positive definite, K_cc
// singular, more than max_dofs DOFs, more than 2^22 steps per period.
#pragma once

#include <Eigen/Dense>

#include "hbf/time_integration.hpp"

namespace hbf::detail {

/// Whether the system has a contact of law unilateral: integrate_steady_state then calls
/// integrate_unilateral_contacts.
bool has_unilateral_contacts(const System& system);
/// The periodic steady state (see above); the state is [y (N), y' (N)] at t = 0 (the massless
/// DOFs' velocities by central differences). The system validated by the caller.
PeriodicResponse integrate_unilateral_contacts(const System& system, double omega,
                                               const TimeIntegrationOptions& options,
                                               const Eigen::VectorXd* initial_state);

}  // namespace hbf::detail
