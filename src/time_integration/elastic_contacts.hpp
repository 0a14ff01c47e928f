// hbfriction — internal: time integration of structures whose contacts have a normal direction
// (law elastic, normal_contact.hpp), the reference for their harmonic balance. Not installed.
//
// Each contact c has tangential directions W_c (N x d, d = 1 or 2), a normal direction n_c and
// a slider s_c (d states). Its mode is one of
//   separated: N = 0, T = 0, and the slider follows, s' = u' (the tangential spring unloaded);
//   stuck:     N = N_0 - k_n g_0 + k_n v > 0, T = k_t (u - s), s' = 0;
//   slipping:  T = mu N t, t = (u - s) / |u - s| (on the cone), and s' = lambda t with
//              lambda = t . u' - mu k_n v' / k_t, which keeps |k_t (u - s)| = mu N;
// with u = W_c^T y, v = n_c^T y. The structure, M y'' + C y' + K y + sum_c (W_c T_c + n_c N_c)
// = F cos(h w t), is integrated by CVODE (Adams or BDF with a dense Jacobian, as options say),
// one period at a time, restarting at t = 0 each period (the excitation phase is exact), until
// the Poincare map converges. Events (CVODE root finding, each root function positive while its
// mode holds): stuck mu N - |T| -> slipping (if lambda > 0 there, else it stays stuck: a graze);
// slipping lambda -> stuck; closed N -> separated (s = u); separated -(N_0 - k_n g_0 + k_n v)
// -> stuck with s = u (T = 0 at closing). Stick, slip and separation times are the event times.
//
// State layout (initial_state, PeriodicResponse::state): [y (N), y' (N), s_1 (d_1), ..., s_m
// (d_m), mode_1, ..., mode_m], mode 0 separated, 1 stuck, 2 slipping; state_size() counts it.
// Inconsistent given states are repaired at t = 0 (the mode from N and the cone, the slider
// projected onto the cone; a slipping contact's slider put on it).
//
// Metrics of the final period: quadratures integrated with the motion (first harmonics,
// friction energy int sum_c (T_c . u_c' + N_c v_c') dt, in which the conservative normal
// spring's part vanishes over a period, viscous and input energies); y_max from 16
// samples_per_period samples refined by a parabola through the largest sample and its
// neighbours; per contact the stick, slip and separated times (ContactRegime).
//
// Refused up front (InvalidInput): a system mixing law elastic with other laws, massless DOFs
// (M must be positive definite), more than max_dofs DOFs (dense M^-1).
#pragma once

#include <Eigen/Dense>

#include "hbf/time_integration.hpp"

namespace hbf::detail {

/// Whether the system has a contact with a normal direction (law elastic): integrate_steady_state
/// then calls integrate_elastic_contacts.
bool has_elastic_contacts(const System& system);
/// The state size of such a system: 2 N + sum_c (d_c + 1).
int elastic_state_size(const System& system);
/// linear_stuck_state for such a system: the static deflection under the preloads with every
/// closed contact's normal spring (the sliders at rest there: no static tangential force), plus
/// the stuck linear response at h omega (every direction's spring), sliders stuck.
Eigen::VectorXd elastic_linear_stuck_state(const System& system, double omega);
/// The periodic steady state (see above); the system validated by the caller.
PeriodicResponse integrate_elastic_contacts(const System& system, double omega, const TimeIntegrationOptions& options,
                                            const Eigen::VectorXd* initial_state);

/// The response's contact summary from its per-contact regimes: the first contact's stick share
/// and regime; regime "none" without contacts.
void summarise_contacts(PeriodicResponse& out);

/// max |y| of a periodic sampled signal, refined by a parabola through the largest sample (and
/// its neighbours).
double refined_max(const Eigen::VectorXd& y);

}  // namespace hbf::detail
