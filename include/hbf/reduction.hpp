// hbfriction — reduction of a finite-element model onto its contact interface (component mode
// synthesis), so that a model from an FE code (M, C, K with thousands of DOFs and a list of
// interface DOFs) becomes a System whose contacts act on physical coordinates.
//
// The FE DOFs split into the retained set b (the interface DOFs, kept as physical coordinates
// in the order given, followed by the DOFs a load acts on that are not interface DOFs: with
// them the reduced model is exact statically for the excitation and the static load) and the
// interior i. The reduced coordinates are q = (y_b, eta), eta the amplitudes of `modes` normal
// modes, and y = T q (T, N x n_r, the recovery matrix: every FE DOF from the reduced
// coordinates; its rows b are [I 0] in every method, so a contact on a retained DOF keeps its
// direction). The reduced matrices are (A^T = transpose):
//
// * craig_bampton (Craig and Bampton 1968): the static constraint modes Psi = -K_ii^-1 K_ib
//   (one sparse LDL^T of K_ii) and the `modes` lowest fixed-interface modes Theta (K_ii theta =
//   lambda M_ii theta, M_ii-normalised): T = [[I, 0], [Psi, Theta]] (rows b, then i),
//   K_r = T^T K T = [[K_bb + K_bi Psi, 0], [0, Lambda]], M_r = T^T M T (the constraint modes'
//   mass and their coupling to the modes kept). Galerkin: with every fixed-interface mode kept
//   (modes = N - n_b) the reduced model is the FE model in other coordinates (exact at every
//   frequency); with fewer, the truncated modes' inertia is lost (an error growing like
//   (w / w_{m+1})^2: say what you need, test it, receptance.hpp's modal form is the same).
// * massless_boundary (the massless-boundary Craig-Bampton method, CBMB; Monjaraz Tec, Gross
//   and Krack 2021, Computers & Structures 247): the constraint modes made M-orthogonal to the
//   kept modes, Psi' = Psi - Theta alpha, alpha = Theta^T (M_ib + M_ii Psi), and their mass
//   dropped: M_r = diag(0, I), K_r = T'^T K T' = [[K_bb + K_bi Psi + alpha^T Lambda alpha,
//   -alpha^T Lambda], [-Lambda alpha, Lambda]]. The retained coordinates are massless (what
//   the rigid contact and the time integrators' static condensation need). Exact statically;
//   with every fixed-interface mode kept it is the FE model with the retained DOFs' mass
//   block M_bb replaced by M_bi M_ii^-1 M_ib: the Schur complement M_bb - M_bi M_ii^-1 M_ib is
//   dropped (with fewer modes, what Craig-Bampton keeps on the retained coordinates,
//   T^T M T's block b minus alpha^T alpha). It is exact only where the retained DOFs carry no
//   mass of their own; a lumped mass on them is dropped whole. ReducedModel::dropped_mass
//   measures it, and warnings() says when it is more than 1 % of the FE model's mass.
// * macneal (MacNeal 1971, with residual flexibility): the `modes` lowest free-interface
//   modes Phi of the whole structure (K phi = lambda M phi) and the residual flexibility
//   R = K^-1 - Phi Lambda^-1 Phi^T at the retained DOFs, G = R_bb: M_r = diag(0, I),
//   K_r = [[G^-1, -G^-1 Phi_b], [-Phi_b^T G^-1, Lambda + Phi_b^T G^-1 Phi_b]] = T^T K T,
//   T = [R E_b G^-1, Phi - R E_b G^-1 Phi_b]. Its receptance at the retained DOFs is exactly
//   Phi_b diag(1 / (lambda_j - w^2)) Phi_b^T + G: the truncated modes enter statically. Needs K
//   and M positive definite and G regular (modes + retained DOFs <= N).
//
// Damping (ReductionOptions::damping): the FE model's C projected, C_r = T^T C T; Rayleigh
// a M_r + b K_r; or modal ratios zeta_j of the reduced model's own normal modes (its pencil
// (K_r, M_r); the massless coordinates condensed statically), C_r = M_r Phi diag(2 zeta_j
// w_j) Phi^T M_r, the last ratio repeated for the higher modes.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>
#include <vector>

#include "hbf/model.hpp"

namespace hbf {

enum class ReductionMethod { craig_bampton, massless_boundary, macneal };
/// "craig-bampton", "massless-boundary", "macneal".
std::string to_string(ReductionMethod method);
/// Inverse of to_string; throws InvalidInput naming the allowed values.
ReductionMethod parse_reduction_method(const std::string& name);

struct ReductionOptions {
    /// The interface DOFs (0-based FE DOFs, distinct), kept as physical coordinates in this
    /// order; may be empty when the loads' DOFs are the only ones kept.
    std::vector<int> interface_dofs;
    /// Normal modes kept: fixed-interface (craig_bampton, massless_boundary; 0 is the static
    /// condensation of Guyan) or free-interface (macneal, >= 1). At most the interior DOFs
    /// (N - retained; macneal: so that the residual flexibility stays regular).
    int modes = 0;
    ReductionMethod method = ReductionMethod::craig_bampton;
    enum class Damping {
        projected,  ///< C_r = T^T C T of the FE model's C (none given: undamped)
        rayleigh,   ///< C_r = rayleigh_mass M_r + rayleigh_stiffness K_r
        modal,      ///< modal_ratios of the reduced model's normal modes
    };
    Damping damping = Damping::projected;
    double rayleigh_mass = 0, rayleigh_stiffness = 0;  ///< a, b >= 0
    std::vector<double> modal_ratios;                  ///< zeta_1, zeta_2, ... in [0, 1)
    /// reduce(System): keep the DOFs the excitation and the static load act on as coordinates
    /// (the reduced model then is statically exact for them). false: only the interface DOFs
    /// are kept and a load on interior DOFs is projected, T^T F, onto the constraint and normal
    /// modes (with a massless boundary a retained loaded DOF is massless: keeping it drops that
    /// node's mass and changes which fixed-interface modes are kept).
    bool retain_loads = true;

    /// Largest reduced model (n_r = retained + modes: its matrices are dense) and largest
    /// recovery matrix T (N x n_r entries, 8 bytes each) the reduction builds.
    static constexpr int max_reduced = 5000;
    static constexpr long long max_recovery_entries = 1LL << 27;  // 1 GB
    /// Throws InvalidInput naming the field: interface DOFs outside 0..dofs-1 or repeated, modes
    /// < 0 (or 0 for macneal) or more than the interior, negative Rayleigh coefficients, ratios
    /// outside [0, 1), and sizes above the limits.
    void validate(int dofs, int retained) const;
};

/// An FE model reduced (see the top of this file).
struct ReducedModel {
    ReductionMethod method = ReductionMethod::craig_bampton;
    SparseMatrix mass, damping, stiffness;  ///< M_r, C_r, K_r (n_r x n_r)
    /// FE DOF (0-based) of each retained coordinate: the interface DOFs, then the loaded ones.
    std::vector<int> retained;
    /// sqrt(lambda_j) of the normal modes kept (fixed- or free-interface), ascending.
    Eigen::VectorXd mode_frequencies;
    /// T (N x n_r): y = T q.
    Eigen::MatrixXd recovery;
    int dofs() const { return static_cast<int>(recovery.rows()); }
    int reduced() const { return static_cast<int>(recovery.cols()); }
    /// The reduced coordinate of FE DOF i, or -1 when i is not retained.
    int coordinate(int dof) const;
    /// T^T v: a force (or force direction) on the FE DOFs as generalised forces.
    Eigen::VectorXd project(const Eigen::VectorXd& v) const { return recovery.transpose() * v; }
    /// massless_boundary and macneal: the mass the massless retained coordinates drop, per
    /// retained coordinate (the diagonal of the dropped block; massless_boundary: Craig-Bampton's
    /// T^T M T on them minus alpha^T alpha; macneal: not measured, empty), and its sum as a
    /// fraction of the FE model's trace(M).
    Eigen::VectorXd dropped_mass;
    double dropped_mass_fraction = 0;
    /// reduce(System) with retain_loads false: the interior FE DOFs the excitation or the static
    /// load act on (their loads projected onto the modes, not statically exact).
    int projected_load_dofs = 0;
    /// FE DOFs clamped before the reduction (unclamped(): their rows of `recovery` are zero).
    int clamped_dofs = 0;
    /// The fraction of dropped mass above which warnings() speaks (1 %).
    static constexpr double dropped_mass_warning = 0.01;
    /// One paragraph: method, sizes, the modes' frequency range, the dropped mass.
    std::string summary() const;
    /// What makes the reduced model doubtful as a model of the FE one: a massless boundary
    /// that drops more than dropped_mass_warning of the mass (where, how much, what to use).
    std::vector<std::string> warnings() const;
};

/// Reduces (M, C, K) (N x N, symmetric; C may be empty) keeping `interface_dofs` and, after
/// them, the DOFs in `loaded_dofs` that are not interface DOFs. Throws InvalidInput naming the
/// key ("reduction.<field>") for bad options and for what makes a method impossible: K_ii
/// singular or indefinite (an unconstrained structure: the constraint modes do not exist), M_ii
/// (or M for macneal) not positive definite, the eigensolver failing, a singular residual
/// flexibility.
ReducedModel reduce(const SparseMatrix& mass, const SparseMatrix& damping, const SparseMatrix& stiffness,
                    const ReductionOptions& options, const std::vector<int>& loaded_dofs = {});

/// An FE System reduced: its matrices as `reduce` with the DOFs its excitation and static load
/// act on retained, the loads projected (T^T F), and every contact's directions (which must act
/// on retained DOFs only) carried to the reduced coordinates. Outputs map with
/// reduced_outputs. Throws InvalidInput naming "contact <c>" for a direction on an interior DOF.
/// A sector model (System::cyclic, cyclic.hpp): the DOFs it shares with the next sector and
/// their masters are added to the interface where missing (kept physical: the wheel of reduced
/// sectors is the reduced wheel), the neighbour pairs carried to the reduced coordinates;
/// macneal is refused (its free-interface modes do not keep the cut faces).
struct ReducedSystem {
    System system;
    ReducedModel model;
};
ReducedSystem reduce(const System& fe, const ReductionOptions& options);

/// FE outputs (terms on FE DOFs) as outputs of the reduced coordinates (rows of T combined),
/// keeping their names.
std::vector<Output> reduced_outputs(const std::vector<Output>& fe_outputs, const ReducedModel& model);

/// DOFs clamped (a system file's `[structure] fixed`): their displacement is zero, so their rows
/// and columns of M, C and K go, and their loads go to the support. `system` has the other DOFs
/// in ascending order: `kept[i]` is the original (0-based) DOF of its DOF i, and `index[d]` the
/// new index of original DOF d (-1 where clamped). A contact keeps its form where its DOFs stay
/// (one against a clamped DOF is against the ground); every direction is carried with the
/// clamped DOFs' entries dropped.
struct ClampedSystem {
    System system;
    std::vector<int> kept;
    std::vector<int> index;
};
/// Clamps `fixed` (0-based DOFs of `s`, distinct, at least one DOF left) in `s`. Throws
/// InvalidInput naming "structure.fixed" for a DOF out of range, repeated, one that carries the
/// excitation or a static load (a force on a support), or when none would be left, for a sector
/// model (System::cyclic), and "contact <c>" for a contact that acts on clamped DOFs only.
ClampedSystem clamp(const System& s, const std::vector<int>& fixed);
/// `outputs` of the unclamped model as outputs of `clamped.system`, names kept, the clamped
/// DOFs' terms dropped (they do not move). Throws InvalidInput naming the output when it has
/// clamped DOFs only.
std::vector<Output> clamped_outputs(const std::vector<Output>& outputs, const ClampedSystem& clamped);
/// A model reduced from a clamped FE model as one of the unclamped model: the recovery matrix
/// gets (zero) rows for the clamped DOFs and `retained` the original DOF numbers, so that
/// coordinate(), reduced_outputs() and the messages use the numbering of the FE model given.
ReducedModel unclamped(ReducedModel model, const ClampedSystem& clamped);

}  // namespace hbf
