// hbfriction — the static contact problem: the structure under its static load
// alone, before the vibration,
//
//     K y + sum_c W_c f_c(W_c^T y) = F_s,
//
// W_c the contact's directions (System::contact_directions) and f_c its law's static force
// (contact_law.hpp: ContactLaw::static_force), the contact loaded monotonically from its unloaded
// state (sliders and internal states at 0; a preload N_0 acting at y = 0). This is the
// holonomic (deformation-theory) solution: it is the incremental one for a load applied
// proportionally in which no contact unloads, and an approximation where one would (the
// redistribution between several slipping contacts). Solved by Newton's method with
// backtracking from y = 0, on the sparse K plus each contact's small Jacobian block. Rigid
// unilateral contacts (law unilateral, whose static force is set-valued) instead solve their
// complementarity problem (normal_contact.hpp: solve_rigid_contacts) on the whole structure,
// G = W^T K^-1 W, loaded in one increment from rest (K must be regular; not mixed with other
// laws).
//
// What it gives: each contact's static state (open, stuck, slipping; presliding for Dahl and
// LuGre), its forces and relative displacements, reported by hbf frf (stderr and the JSON
// summary), and harmonic balance's first guess of harmonic 0 (its mean state) when the system
// has a static load. Harmonic balance itself balances harmonic 0 with the load and the contact
// forces' means. Where a contact sticks throughout the period its periodic state is a family
// (the slider anywhere in an admissible set), and which member a structure settles on depends on
// its history (how the load and the vibration were applied): harmonic balance takes the one with
// the largest stick margin (normal_contact.hpp: the centred slider), whose mean tangential force
// is near 0, not this static state's slider, whose force is the static one. Time integration
// started from this state (hbf timeint with a static load) keeps the static slider while it
// sticks; the two then differ by that mean force. (Taking the static slider in harmonic balance
// where it is admissible, and the nearest admissible point where not, was tried: it is
// continuous but puts corners into the branch where the vibration's stick range opens, at the
// stick-slip/stick transitions, which the continuation could not pass on liftoff3.toml.)
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/model.hpp"

namespace hbf {

struct StaticContactState {
    std::string state;         ///< "open", "stuck", "slipping", "presliding"
    Eigen::VectorXd relative;  ///< q along each of the contact's directions (normal last)
    Eigen::VectorXd force;     ///< the contact's force along each direction (the normal force last)
    Eigen::VectorXd slider;    ///< law elastic: the tangential slider (StaticForce::slider)
};

struct StaticState {
    bool ok = false;
    std::string message;            ///< why not, when !ok
    Eigen::VectorXd displacement;   ///< y_s (N)
    std::vector<StaticContactState> contacts;
    int iterations = 0;             ///< Newton steps
    double residual = 0;            ///< |K y + sum W f - F_s|_inf over the force scale
};

/// Whether the system has anything static to solve: a static load, or a contact whose law
/// acts at rest (a preload: StuckElement::offset != 0).
bool has_static_problem(const System& system);

/// The static state (see the top of this file). System::validate first (throws InvalidInput).
/// Not ok, with the reason, where a law has no single-valued static force (exact Coulomb),
/// the static stiffness is singular (a part held only by contacts that open or slip; rigid
/// contacts: K singular), rigid contacts are mixed with other laws, or Newton's method does not
/// reach 1e-10 of the force scale within 100 steps (rigid contacts: 1e-12 of their forces).
StaticState static_state(const System& system);

/// Each contact's linear elements while it sticks (ContactLaw::stuck_directions), about the
/// static state where the system has a static load and a contact with a normal direction: a
/// contact the load presses (static normal force > 0) sticks with its springs even without a
/// preload of its own (an interface's preload_pressure is such a load). The linear limits
/// (stuck_linear_response, linear_resonances), harmonic balance's first guess and time
/// integration's stuck start use it. Without a static load, or where the static state is not
/// solved: stuck_directions.
std::vector<std::vector<StuckElement>> stuck_elements(const System& system);

/// What makes penalty contacts (law elastic) hard or surprising, one line each (empty when
/// nothing does): a normal or tangential stiffness above `penalty_ratio` times the structure's
/// own static stiffness along that direction (1 / w^T K^-1 w; not judged where K is singular):
/// harmonic balance then meets impacts and stick-slip kinks sharper than its harmonics resolve;
/// and, with `rest` (the static state), a preload N_0 the structure relieves below 1 % at rest
/// (N = N_0 k / (k + k_n) for one contact: the preload is the normal force at zero
/// displacement, not a load that stays). Above 8 such contacts the first and a count.
struct PenaltyDiagnostics {
    std::vector<std::string> stiff;     ///< stiffnesses far above the structure's (a note)
    std::vector<std::string> relieved;  ///< preloads relieved at rest (a warning: likely not meant)
};
PenaltyDiagnostics penalty_diagnostics(const System& system, const StaticState* rest, double penalty_ratio = 1e3);

/// "contact 1: stuck (N = 1.2, |T| = 0.3), contact 2: open": one line for messages; above 8
/// contacts "99 contacts: 90 stuck, 9 open (N from 0 to 9.8, |T| up to 0.05)".
std::string describe(const StaticState& state);

}  // namespace hbf
