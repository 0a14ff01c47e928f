// hbfriction — the event-exact solver on finite-element models: their modal form.
//
// The exact solver's flows are dense in the DOFs with mass (event_exact.hpp): up to
// exact_solver_max_dofs. A larger structure M y'' + C y' + K y + W f = F cos(w t) (M and K
// positive definite, C diagonal in the modal basis: Rayleigh or modal damping) is replaced by
// its Ritz projection on the basis that harmonic balance's `modes` option uses
// (receptance.hpp): the m lowest modes Phi (M-normalised, K Phi = M Phi Lambda, c_j =
// phi_j^T C phi_j) and, for the truncated modes, one residual attachment mode per contact,
//     Psi = R W R_c^-1,   R = K^-1 - Phi Lambda^-1 Phi^T,   R_c = W^T R W
// (the static deflection of the truncated modes under the contact forces, scaled so that
// W^T Psi = I). With y = Phi q + Psi r, the structure's equations projected on [Phi, Psi]
// are exact identities of R (R K R = R, Phi^T M R = 0, Phi^T K R = 0):
//     q'' + diag(c) q' + Lambda q = Phi^T F cos + P g                 (P = Phi^T W)
//     mu r'' + C_r r' + R_c^-1 r  = R_c^-1 W^T R F cos + g
// with mu = Psi^T M Psi, C_r = Psi^T C Psi (a mu + b R_c^-1 for Rayleigh damping) and g = -f the
// contacts' forces on the structure; the contacts see u = W^T y = P^T q + r. The load's
// residual that Psi does not carry, d = R F - Psi W^T R F (W^T d = 0: no contact moves it;
// K-orthogonal to Psi), is one more Ritz vector, y = Phi q + Psi r + d s, whose coordinate s
// is cos(w t) at w = 0. So the exact solver runs on m + n_c + 1 DOFs, all with mass, whatever
// N. The Ritz vectors are projected exactly: M and C through their products, K through the
// identities (B^T K B = diag(R_c^-1, d^T K d)); mu couples r and s. Each Ritz vector is scaled
// to unit modal mass in the model (so are its coordinate and the contact direction).
// A contact whose residual compliance vanishes (every mode kept: (R_c)_cc <= 1e-12 of its
// static compliance w^T K^-1 w) has no attachment mode: it acts on q along p_c.
//
// Where the truncation enters (the exact orbit of this model differs from the structure's):
// the truncated modes respond through the attachment modes only: exactly at w = 0 (the static
// residual) and to second order in k w (their mass mu and, for Rayleigh damping, their damping
// are the truncated modes' own), so that the error of the contacts' receptance is of the order
// (k w)^4 / lambda_{m+1}^2 of the residual part for harmonic k of the contact forces.
// Measured on the 200-DOF beam: README and tests/test_modal_exact.cpp.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "hbf/model.hpp"

namespace hbf {

class ModalExactModel {
public:
    /// The modal form of `system` with `modes` modes (fewer when the structure has fewer DOFs).
    /// Throws InvalidInput naming why not: modes out of 1..largest_exact_modes, M or K not
    /// positive definite, C not diagonal in the modal basis, the contacts' residual compliance
    /// singular, a contact with base motion, an excitation harmonic other than 1.
    ModalExactModel(const System& system, int modes);

    /// The modal structure [q (m), r (one per contact with an attachment mode), s (the
    /// load's residual, when F has one)] and its contacts.
    const System& system() const { return modal_; }
    int modes() const { return static_cast<int>(lambda_.size()); }
    /// Natural frequencies sqrt(lambda_j) of the modes kept, ascending.
    Eigen::VectorXd natural_frequencies() const { return lambda_.cwiseSqrt(); }
    /// The output c^T y of the structure as an output of the modal form (same name).
    Output output(const Output& original) const;
    /// A state of the structure (time_integration.hpp's layout: [y, y', internal, mode]) as one
    /// of the modal form: q = Phi^T M y (the modes' share), r = W^T y - P^T q, s = 1; the
    /// contacts' internal states and modes as given.
    Eigen::VectorXd reduce_state(const Eigen::VectorXd& state) const;

private:
    System modal_;
    int dofs_ = 0;                  // N of the structure
    Eigen::VectorXd lambda_;
    Eigen::MatrixXd to_modal_;      // Phi^T M (m x N)
    Eigen::MatrixXd phi_;           // N x m
    Eigen::MatrixXd directions_;    // W (N x n_c)
    Eigen::MatrixXd p_;             // Phi^T W (m x n_c)
    Eigen::MatrixXd residual_basis_; // [Psi, d] (N x (contacts with an attachment mode + 1 if d))
    Eigen::VectorXd residual_scale_; // their scales to unit modal mass
    std::vector<int> r_index_;      // per contact: its r DOF in the modal form, -1 if none
    int load_index_ = -1;           // s, -1 without a load residual
};

/// The modes the exact solver's modal form uses unless told otherwise. The attachment modes carry
/// the truncated modes to second order in k w, so few are needed: measured on the 200-DOF beam
/// (contact at the tip, force at mid-span; w = 40, 75, 160), y_max with 20 modes agrees with
/// 62 modes to 1e-11 and with 10 modes to 1e-8 (tests/test_modal_exact.cpp), while a period
/// costs more with every mode between w and the split (event_exact.hpp).
constexpr int automatic_exact_modes = 20;

/// Modes of the modal form the exact solver (and the polish) use for `system`: 0 where the
/// exact solver takes the structure itself (exact_solver_supports, or a refusal that the modal
/// form does not lift: a law it does not cover, h > 1), else `modes` (0: automatic_exact_modes)
/// capped at exact_solver_max_dofs. The polish and hbf frf pass 0: harmonic balance's own
/// `modes` (a static residual only) is its business, not the exact solver's.
int exact_solver_modes(const System& system, int modes = 0);

/// The most modes a modal form of `system` may keep: its N, and exact_solver_max_dofs less one
/// Ritz vector per contact and one for the load.
int largest_exact_modes(const System& system);

/// The polish chooses the modes by their effect (exact_polish.hpp): the smallest count of
/// 10, 20, 40, largest_exact_modes whose exact orbit at the branch's highest frequency changes
/// by at most this with the next count (the outputs' maxima relative to the largest, the
/// friction energy relative to the excitation's work).
constexpr double modal_truncation_tolerance = 1e-9;
/// The estimated truncation above which a polish on the modal form is doubtful (a warning of
/// the FRF; an automatic polish is declined before its work).
constexpr double modal_truncation_warning = 1e-6;

}  // namespace hbf
