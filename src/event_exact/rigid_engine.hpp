// hbfriction — internal to event_exact: the flow engine of rigid unilateral contacts with
// Coulomb friction (law unilateral) on the massless DOFs of a structure
// (contact/massless_contacts.hpp), in 2D: each contact has one tangential direction.
//
// The state is zhat = [y_m, y_m', s, cos(w t), sin(w t), 1]: the DOFs with mass, their
// velocities and per contact its tangential displacement s (where a stuck contact is held).
// The massless nodes follow statically, so the contact forces lambda are algebraic: in each
// pattern (per contact open, stuck, or slipping in the + or - direction) they solve
//   open:      lambda_T = 0, lambda_N = 0;
//   closed:    q_N = g_0                      (q = q0 - G lambda, massless_contacts.hpp);
//   stuck:     q_T = s;
//   slipping:  lambda_T = sigma mu lambda_N   (sigma = +1 or -1: the slip's direction);
// linear in zhat: lambda = Lambda_m zhat. The structure's motion is then linear,
//   M_mm y'' + C_mm y' + K_mm y + K_mc y_c = F_m cos + S_m,
//   y_c = K_cc^-1 (F_c cos + S_c - K_cm y - W lambda),
// and so is s' (0 while stuck; q_T' otherwise, which keeps s = q_T): each pattern is an
// autonomous linear system zhat' = A_m zhat, flowed in closed form by PatternEngine.
// The contact forces and the nodes' positions are continuous across every event (an event
// happens where two patterns' equations agree), so y, y' are continuous and only s' jumps
// (at a closing into stick, at a slip's start).
//
// Guards (positive while the pattern holds): open, the gap g_0 - q_N; closed, lambda_N;
// stuck, mu lambda_N -+ lambda_T; slipping, the slip velocity sigma q_T'. After an event the
// contact takes the first pattern (in the order the event suggests) whose guards are positive
// or zero and not decreasing there; where none is (a touch of the boundary: grazing), it keeps
// its pattern.
#pragma once

#include <Eigen/Dense>
#include <string>

#include "contact/massless_contacts.hpp"
#include "event_exact/engine.hpp"

namespace hbf::detail::exact {

/// A contact's pattern in RigidEngine.
enum RigidMode : int { rigid_open = 0, rigid_stuck = 1, rigid_slip_positive = 2, rigid_slip_negative = -2 };

/// The guards' kinds (Guard::kind).
enum RigidGuard : int { guard_gap = 0, guard_normal = 1, guard_limit_positive = 2, guard_limit_negative = 3,
                        guard_slip = 4 };

class RigidEngine : public PatternEngine {
public:
    /// Throws InvalidInput where split_massless_contacts does, for a contact with two tangential
    /// directions (3D) and for a force at a harmonic other than the fundamental.
    RigidEngine(const System& system, double omega, bool split = true);

    const MasslessContacts& split() const { return s_; }
    int tangential(int c) const { return s_.blocks[static_cast<std::size_t>(c)].first; }
    int normal(int c) const { return s_.blocks[static_cast<std::size_t>(c)].first + 1; }
    int slider(int c) const { return 2 * n_dofs_ + c; }
    int directions(int) const { return 1; }  ///< tangential directions of a contact
    int tangential_entries() const { return n_contacts_; }
    const System& system() const { return system_; }

    Modes settle(const Eigen::VectorXd& zhat, Modes modes, const Guard& trigger) override;

    /// The patterns of a state (zhat's y and the sliders s of contacts stuck before it), from
    /// the static contact problem with s as the tangential reference; sets every slider to the
    /// contact's tangential displacement (so zhat is consistent with the patterns).
    Modes initial_modes(Eigen::VectorXd& zhat);

    /// Whether pattern `modes` holds at zhat for contact c: its guards positive, or zero and
    /// not decreasing (relative tolerance `tolerance` of the guard's terms).
    bool holds(const Eigen::VectorXd& zhat, const Modes& modes, int c, double tolerance);

    /// Puts zhat on the pattern's relations at time t: the forcing's states, and the sliders
    /// of the contacts not stuck at their tangential displacement.
    void make_consistent(Eigen::VectorXd& zhat, const Modes& modes, double t) {
        mode(modes);
        restore_constraints(zhat, modes, t);
    }

private:
    ModeData build(const Modes& modes) const override;
    /// The forcing, and the sliders of contacts not stuck at their tangential displacement.
    void restore_constraints(Eigen::VectorXd& zhat, const Modes& modes, double t) const override;

    const System& system_;
    MasslessContacts s_;
    Eigen::MatrixXd free_;          ///< q0 as rows over zhat (lambdas x n)
    Eigen::MatrixXd free_nodes_;    ///< y_c without contact forces, rows over zhat
    Eigen::MatrixXd base_;          ///< M^-1 (forces on the masses without contact forces), rows
    Eigen::MatrixXd transmit_;      ///< M^-1 K_mc B: the contact forces' effect on y''
};

}  // namespace hbf::detail::exact
