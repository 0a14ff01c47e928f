// hbfriction — periodic orbits of structures whose contacts have a normal direction and mass at
// the nodes (law elastic: a normal spring that opens, a tangential spring and a slider on the
// friction cone; normal_contact.hpp), with their Floquet multipliers.
//
// The state is the whole motion, [y, y', the sliders] (elastic_contacts.hpp's convention), and
// the periodic orbit is a fixed point of the period map P, solved by Newton's method on P(z) - z
// from a section at t = 0. P is law elastic's event-driven flow (CVODE, Adams, the closing,
// opening, stick and slip events located by root finding) at a relative and absolute tolerance of
// elastic_flow_tolerance; Newton's matrix is the flow's own derivative over the period, the
// variational equation integrated with the motion and the saltation matrices of the events
// (Phi+ = D R Phi- + (f+ - D R f-) grad g^T Phi- / (grad g^T f-): the time shift of each event and
// the slider's reset at an opening or a closing). Its eigenvalues are the Floquet multipliers.
// Between the events the flow is smooth, so P is differentiable wherever no event grazes (a root
// touched without crossing) or two contacts' events coincide. Where the variational equation is
// stiff (in 3D, a slip next to an opening or a closing: the slip direction turns as fast as the
// normal force vanishes, and Adams' fixed-point iterations fail or crawl), Newton's matrix and the
// multipliers are central differences of P instead (steps of 1e-5 of the state's size, each
// perturbed state's modes settled; about 1e-5 accurate; the message says so). On models with more
// than elastic_variational_max_states continuous states no matrix is formed: Newton-Krylov (GMRES
// on (P' - I) u = -(P(z) - z) to 1e-3 of the residual, each product P' v a central difference of
// P along v: two periods), and the dominant multipliers by Arnoldi on the same products at the
// orbit (the Ritz values whose residual estimate is below 1e-5, the 10 largest of modulus >=
// 0.05 converged or said so; at most 120 vectors): multipliers contains those, not all c.
//
// The sliders of contacts slipping at t = 0 lie on their cone and those of open contacts at
// their node (s = u): each iterate is put back there. Multipliers at 1: a contact stuck all
// period can hold its slider anywhere that keeps it inside its cone (the orbits form a family,
// as for law unilateral), and a contact slipping or open all period conserves a perturbation of
// its slider along the constraint. Newton's steps are least-squares solutions, so those
// directions take no step: the orbit is the family's member nearest the start.
//
// Accuracy: the orbit is that of the flow at the stated tolerance, within about 1e-9 of its
// scale; Newton stops at options.tolerance or where its residual is below 1e-9 and a step no
// longer lowers it (the message says so). Cost: each Newton iteration integrates c + 1 columns
// (c = 2 N + the slider components) with the motion, about c^3 operations a step, or 2 c + 1
// periods by differences; beyond elastic_variational_max_states, two periods per GMRES step and
// per Arnoldi step (at most 240 each).
#pragma once

#include <Eigen/Dense>
#include <string>

#include "hbf/event_exact.hpp"
#include "hbf/model.hpp"

namespace hbf {

/// The flow's relative and absolute tolerance (the absolute one of the response's scale, as
/// time_integration.hpp's absolute_tolerance).
constexpr double elastic_flow_tolerance = 1e-11;
/// The most continuous states (2 N + the slider components) the solver takes (its dense flow
/// costs about c^2 operations an evaluation).
constexpr int elastic_solver_max_states = 600;
/// Up to this many continuous states Newton's matrix is the variational equation's (about c^3
/// operations a step); beyond, Newton-Krylov on central differences of the period map.
constexpr int elastic_variational_max_states = 64;

/// True when the system has contacts and every one is of law elastic.
bool elastic_contacts_only(const System& system);

/// The continuous states of law elastic's flow: 2 N + one slider component per tangential
/// direction of each contact (the state's last entries, one mode per contact, are discrete).
int elastic_continuous_states(const System& system);

/// Why elastic_periodic_orbit cannot take `system` (one sentence naming the cause), empty when it
/// can: every contact of law elastic, M positive definite, at most elastic_solver_max_states
/// continuous states.
std::string elastic_solver_refusal(const System& system);

/// The periodic orbit at omega near `initial_state` (elastic_contacts.hpp's state: [y (N), y'
/// (N), sliders, modes (0 open, 1 stuck, 2 slipping)]; empty: from rest, the static state under
/// the preloads). options.warmup_periods plain periods first, then Newton; where Newton stalls,
/// again after 8, 32, 128, ... plain periods (options.restarts). options.max_events_per_period
/// counts per contact here (a meshed interface's nodes each have their events). ExactOrbit as in
/// event_exact.hpp, with: state in this convention; events' modes 0, 1, 2; contacts[c] with the
/// open share; friction_force (samples) the first tangential component; y_max from 4096 samples
/// a period refined by a parabola (within about 1e-11 of the maximum); energy the contact
/// forces' work over the period (the normal springs' part vanishes on an orbit);
/// permanent_stick true when every contact is stuck all period (the member the start holds).
/// Throws InvalidInput where elastic_solver_refusal is not empty, for omega <= 0, bad options or
/// a state of the wrong size. Non-convergence is a status (converged = false, message).
ExactOrbit elastic_periodic_orbit(const System& system, double omega, const Eigen::VectorXd& initial_state,
                                  const ExactOptions& options = {});

/// A start for elastic_periodic_orbit from a periodic motion: `displacement` sampled at equal
/// steps over one period from t = 0 (samples x N), `velocity` y'(0). Each contact's slider and
/// mode at t = 0 come from the element's periodic cycle on the samples (normal_contact.hpp:
/// march), as harmonic balance has them. Throws InvalidInput for mismatched sizes.
Eigen::VectorXd elastic_start_state(const System& system, const Eigen::MatrixXd& displacement,
                                    const Eigen::VectorXd& velocity);

}  // namespace hbf
