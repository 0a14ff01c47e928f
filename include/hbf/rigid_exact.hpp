// hbfriction — exact periodic orbits of structures whose contacts are rigid unilateral contacts
// with Coulomb friction (law unilateral) on massless nodes: a massless-boundary reduction, or
// any model whose contact DOFs carry no mass. 2D contacts (one tangential direction) and 3D
// ones (two: a friction cone).
//
// The massless nodes follow the masses statically, so between two contact events (a node's
// closing or opening, its stick or slip start) the contact forces follow from the state of the
// DOFs with mass, and the events are the roots of the contact conditions (a node's gap, normal
// force, friction margin, slip velocity). With 2D contacts the motion between events is a
// linear system, flowed in closed form, and the period map's derivative (the monodromy) is
// exact: the segment exponentials and the saltation matrices at the events. A 3D contact's
// slip direction is a state of its own (a massless node's slip turns at a finite rate), the
// motion while it slips is nonlinear and flowed by Taylor series of order 30 with steps whose
// truncation is below rounding, or where the directions are stiff (their relaxation far faster
// than the period) by implicit collocation steps (ConeStepping). For 3D contacts, Newton's
// matrix and the Floquet multipliers come from the flow's own derivative over a period (the
// variational equation along the steps and the saltation at the events, updated by Broyden's
// formula between fresh ones). Where a Newton step with a fresh derivative fails, or Newton's
// residual (above 1e-6) has not fallen tenfold in 8 iterations (a derivative that is off, below),
// Newton restarts (ExactOptions::restarts: plain periods from its last iterate, a new section);
// in the last attempt, or where the derivative is not available, Newton's steps are solved by
// GMRES on central differences of the period map (steps of 1e-6 of the state's size; two periods
// a product), preconditioned by the flow's last Newton matrix. The periodic orbit is the fixed point of the
// period map, solved by Newton's method; its derivative's eigenvalues are the Floquet
// multipliers. Where contacts of a symmetric interface change pattern at one instant and are
// coupled, the period map is only piecewise differentiable and the flow's derivative through
// that instant follows the order in which rounding puts the events: it can be far off. So the
// derivative at the orbit is checked along one direction against a central difference of the
// period map (two periods; again with steps of 1e-8 where those of 1e-6 meet other events), and
// where they differ by more than 1e-3 the multipliers are the
// dominant ones of the period map's central differences, by Arnoldi (two periods a product;
// those of modulus >= 0.05 among the 10 largest converged to about 1e-8 or said so:
// multipliers then holds those, not all; the message says so; the nodes stuck all period held
// through them and their held positions left out, each a multiplier 1); except where the
// perturbed periods have another number of events at some contact than the orbit and no two
// contacts change pattern at one instant independently (a cascade, one node's event making
// another stick or slip at its instant, does not count): a contact grazing an edge of its
// friction cone or its gap (a node stuck all period whose force touches the cone's edge at an
// instant, as a shakedown leaves it), where the period map has a kink that the differences
// straddle; the multipliers are then the flow's own, of the orbit's side of the kink (the
// message says so). On a symmetric orbit of a mirror-symmetric structure (src/model/mirror.hpp;
// the orbit's unknowns their mirror images' to 1e-8 of the differences' unit) the period map's
// derivative commutes with the mirror and the multipliers split: those of the symmetric changes
// from the flow's derivative where a central difference along a symmetric direction confirms it
// (to 1e-3), those of the antisymmetric changes by Arnoldi on them alone (about half the
// products); each product's symmetric part is measured, and above 1e-6 of its direction Arnoldi
// takes all the free unknowns again (the message says which). Along antisymmetric changes the
// map is only piecewise smooth at such an orbit (the mirror images' events part either way) and
// central differences there depend on the direction: those multipliers are defined to about
// 1e-4 (docs/methods/contact-laws-hb.md). The two perturbed periods of every central difference flow at once on two
// threads (ExactOptions::threads; the second on a copy of the engine), which halves the time of
// the products, not their number. Patterns, events and the choice of the pattern after an event:
// src/event_exact/rigid_engine.hpp (2D) and src/event_exact/cone_engine.hpp (3D).
#pragma once

#include <Eigen/Dense>
#include <string>

#include "hbf/event_exact.hpp"
#include "hbf/model.hpp"

namespace hbf {

/// True when the system has contacts and every one is of law unilateral: the systems this
/// solver is for (the exact polish of an FRF then uses it).
bool rigid_contacts_only(const System& system);

/// True when rigid_contacts_only holds and a contact has a second_direction (3D): the FRF's
/// polish is then off unless asked for (where the slip directions are stiff the flow takes
/// implicit steps and the multipliers difference the period map: costly on meshed interfaces).
bool rigid_contacts_3d(const System& system);

/// Why ExactOptions::mirror_symmetric would do nothing on `system` (one sentence naming the
/// cause: its contacts are not law unilateral's 3D ones, or it has no mirror symmetry, a
/// reflection of its DOFs that leaves M, C, K, the loads and the contacts unchanged), empty
/// when the option applies.
std::string mirror_symmetric_refusal(const System& system);

/// The most contacts the rigid-contact exact solver takes: each step solves the contact
/// equations (size 2 or 3 per contact) with a dense LU, whose cost grows as their cube.
constexpr int rigid_solver_max_contacts = 256;

/// Why the rigid-contact exact solver cannot take `system` (one sentence naming the cause),
/// empty when it can: every contact of law unilateral, the contact directions on massless
/// undamped DOFs, K regular on them, M positive definite on
/// the others, the force at the fundamental, at most exact_solver_max_dofs DOFs with mass and
/// rigid_solver_max_contacts contacts.
std::string rigid_solver_refusal(const System& system);

/// The periodic orbit at omega near `initial_state`: [y (N), y' (N)] of every DOF (the
/// convention of law unilateral's time integration; the massless DOFs' part of y sets where
/// stuck contacts are held, their velocities are not used), or empty for a start at rest.
/// ExactOrbit's fields as in event_exact.hpp, with these differences: state is [y (N), y' (N)]
/// at t = 0 (the massless DOFs' velocities those of the orbit); the events' modes are
/// 0 open, 1 stuck, +2 / -2 slipping in the + / - tangential direction (3D: 2 slipping);
/// contacts[c] has the separated share, the normal force's mean and half range and the friction
/// energy, exact; friction_force holds the tangential contact forces (3D: along the first
/// tangential direction); stick_margin_min/max are contact 1's stick indicator as law
/// unilateral's time integrator has it (|lambda_T| / (mu lambda_N) - 1 stuck, 0 slipping,
/// 1 open) on 64 points a step.
/// Permanent stick (every contact stuck all period) is degenerate: any held position that
/// keeps the nodes in their friction cones is periodic. Convention: the nodes held where the
/// start holds them (its massless DOFs' tangential displacements; the static state's for a
/// start at rest) when the orbit about them sticks throughout (permanent_stick = true), else
/// the orbit Newton found. A given start (not rest) that holds every contact stuck is tried
/// first as such an orbit, without the warm-up and the general solve: a plain period checks that
/// no node leaves stick, the stuck structure's orbit about the held positions follows in closed
/// form (3D contacts; 2D: from one period with the derivative; the stuck structure is linear),
/// and a recorded period confirms (a few periods instead of a dozen: a sweep through stick).
/// 3D contacts: where nodes slip in that first period, plain periods follow while each slipping
/// node slips once a period and none opens (a shakedown, at most 30), then the orbit about where
/// they settled (the message says how many periods); otherwise the general solve takes over.
/// Newton stops at options.tolerance, or where no step lowers a residual below 1e-9 (the
/// rounding of the flow over a period: converged, the message and residual say so).
/// Throws InvalidInput where rigid_solver_refusal is not empty, for omega <= 0, bad options
/// or a state of the wrong size. Non-convergence is a status (converged = false, message).
ExactOrbit rigid_periodic_orbit(const System& system, double omega, const Eigen::VectorXd& initial_state,
                                const ExactOptions& options = {});

/// How the flow of 3D contacts steps between events: automatic (Taylor series of order 30
/// where their steps are longer than a thousandth of the period, else implicit Radau IIA
/// collocation with a local error of 1e-12 of the state's size: a slipping node's direction
/// relaxes at |q_T'| / (G mu lambda_N), on a meshed interface thousands of times a period),
/// Taylor series only, or collocation only. 2D contacts are flowed in closed form either way.
enum class ConeStepping { automatic, taylor, collocation };

/// Newton's steps for 3D contacts: automatic (Newton's matrix from the flow's derivative,
/// updated by Broyden's formula; GMRES on central differences of the period map where the
/// derivative is missing or a step with it fails), or GMRES on central differences from the
/// first step, and the multipliers by Arnoldi on them (tests, benchmarks). 2D contacts take the
/// exact monodromy either way.
enum class ConeNewton { automatic, differences };

/// rigid_periodic_orbit with a chosen stepping and Newton's steps (tests, benchmarks).
ExactOrbit rigid_periodic_orbit(const System& system, double omega, const Eigen::VectorXd& initial_state,
                                const ExactOptions& options, ConeStepping stepping,
                                ConeNewton newton = ConeNewton::automatic);

}  // namespace hbf
