// hbfriction — the harmonic-balance residual R(X, omega) and its Jacobians.
//
// Unknowns X: the coefficients (fourier.hpp layout, 2H+1 each) of every DOF y_i, then of the
// internal state z_c of every state-law contact. With Y the (2H+1) x N matrix whose column i
// holds the coefficients of y_i, D = omega D1 the derivative with respect to tau, the
// structure's rows are (M, C, K symmetric)
//
//     R_Y = D^2 Y M + D Y C + Y K + sum_c f_c w_c^T - e_cos_h F^T,
//
// i.e. the Galerkin projection of M y'' + C y' + K y + sum_c w_c f_c - F cos(h omega tau) on
// 1, cos k theta, sin k theta; f_c are the friction force coefficients of contact c computed
// from q_c = Y w_c (and z_c) by the AFT (contact_force.hpp), and each state-law contact adds its
// state residual r_z. Both Jacobians are exact (no finite differences).
//
// A sector of a cyclically symmetric wheel (System::cyclic, cyclic.hpp) is balanced in the full
// formulation on its independent DOFs: X = P U, P turning each dependent DOF's harmonic k by
// k phi from its master's, and R_U = P^T R_X (the wheel's rows of the independent DOFs).
//
// Two formulations of the same equations (HarmonicBalanceOptions::formulation):
// * full: the unknowns are the coefficients of every DOF (above); the Jacobian is dense in
//   N (2H+1), so it serves small systems and tests;
// * condensed (the default): the linear structure is solved exactly per harmonic
//   (receptance.hpp), Q_k = W^T Z_k^-1 F_k - G_k Lambda_k, so the unknowns are only the
//   contacts' relative displacements q_c (2H+1 coefficients each) and the internal states.
//   With Gr the real form of G_k (per harmonic k, G_k = a + i b acts on (c_k, s_k) as
//   [[a, b], [-b, a]], G_0 real) the residual of contact c, harmonic k, is
//       R_c,k = ( q_c - q0_c + sum_d Gr_cd f_d )_k / min(|G_k,cc|, G_0,cc),
//   q0 = W^T Z_h^-1 F on the excitation harmonic h (1 by default); R is a force. Where the
//   structure is stiffer than statically (high harmonics, |G_k| < G_0) the rows of one contact on one DOF equal the full
//   formulation's up to their sign (the same conditioning); near a resonance of the structure
//   without contacts (|G_k| large) the static stiffness 1 / G_0,cc keeps the rows sensitive to
//   q; the scale is bounded near an antiresonance (G_k,cc -> 0). Any DOF is recovered afterwards from the contact forces:
//   Y_k = Z_k^-1 (F_k - W Lambda_k). The cost per evaluation no longer grows with N beyond
//   the sparse factorisations of Z_k at each new omega.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hbf/fourier.hpp"
#include "hbf/contact_force.hpp"
#include "hbf/model.hpp"
#include "hbf/receptance.hpp"
#include "hbf/static_state.hpp"
#include "hbf/structured_jacobian.hpp"

namespace hbf {

/// How the linear structure enters the unknowns (see the top of this file).
enum class Formulation {
    automatic,  ///< condensed when the system has contacts and the shifted static problem is
                ///< regular, else full
    full,       ///< every DOF's coefficients are unknowns (dense; small systems, tests)
    condensed,  ///< the contacts' relative displacements only (any size; needs K invertible)
};
/// "automatic", "full", "condensed".
std::string to_string(Formulation formulation);
/// Inverse of to_string; throws InvalidInput naming the allowed values.
Formulation parse_formulation(const std::string& name);

/// How the corrector and the tangent hold and solve dR/dX (structured_jacobian.hpp).
enum class JacobianForm {
    automatic,   ///< structured where allowed and the unknowns exceed structured_threshold (laws with
                 ///< internal states other than unilateral: max_unknowns), else dense
    dense,       ///< formed densely, solved by dense factorisations (Ceres); at most max_unknowns
    structured,  ///< condensed, every harmonic: I + Gr Df (and the internal states' blocks) kept in
                 ///< its structure, Newton with preconditioned GMRES; for interfaces of many nodes
};
/// "automatic", "dense", "structured".
std::string to_string(JacobianForm form);
/// Inverse of to_string; throws InvalidInput naming the allowed values.
JacobianForm parse_jacobian_form(const std::string& name);

struct HarmonicBalanceOptions {
    int harmonics = 10;    ///< H >= 1: harmonics 0..H are balanced
    int time_samples = 0;  ///< N_t > 2H; 0 chooses Fourier::default_time_samples(H)
    Formulation formulation = Formulation::automatic;
    /// Condensed formulation only: 0 solves the structure directly (sparse LU per harmonic and
    /// frequency: cost linear in N); m > 0 uses the m lowest modes plus the static residual
    /// flexibility (receptance.hpp: cost independent of N; needs M > 0, K > 0 and C diagonal in
    /// the modal basis). >= 0.
    int modes = 0;
    /// Balance the odd harmonics 1, 3, 5, ... <= H only (no constant, no even harmonics): the
    /// half-wave symmetric solutions y(t + T/2) = -y(t) of a symmetric problem, with half the
    /// unknowns. Every friction law here is odd (f(-q, -v) = -f(q, v) with z -> -z) and the
    /// force F cos(h w t) is half-wave symmetric for odd h, so such solutions exist whenever h
    /// is odd (required); an orbit that breaks the symmetry (a symmetry-breaking bifurcation)
    /// is not found. The AFT runs on all samples as before, so each evaluation costs the same;
    /// the corrector's and the tangent's linear algebra shrink (~1/8 for the dense solves).
    bool odd_harmonics = false;
    /// dR/dX dense or in its structure (JacobianForm).
    JacobianForm jacobian = JacobianForm::automatic;

    /// The ranges of hbf and Python (HarmonicBalance itself takes any H >= 1): throws
    /// InvalidInput naming the field: harmonics 1..max_harmonics (model.hpp: above it a branch
    /// takes many minutes); time_samples 0 (automatic) or 2 harmonics + 1..max_time_samples;
    /// modes 0 (direct solve) or 1..max_modes.
    void validate() const;
    static constexpr int max_time_samples = 65536;
    static constexpr int max_modes = 100000;
};

/// Work counters of HarmonicBalance::evaluate, for benchmarks and summaries.
struct EvaluationStatistics {
    long long residuals = 0;        ///< calls of evaluate
    long long jacobians = 0;        ///< of them, calls that asked for dR/dX
    double aft_seconds = 0;         ///< AFT: transforms and friction laws on the time samples
    double jacobian_seconds = 0;    ///< chain rule through the AFT and assembly of dR/dX, dR/domega
    double structure_seconds = 0;   ///< the linear structure's part of the residual
};
/// The work done between two snapshots of the counters.
EvaluationStatistics operator-(const EvaluationStatistics& later, const EvaluationStatistics& earlier);

class HarmonicBalance {
public:
    /// The bound on the unknowns (before the odd-harmonic selection): the Jacobian is dense.
    static constexpr int max_unknowns = 6000;
    /// Automatic choice: the structured Jacobian above this many unknowns (where it is allowed).
    static constexpr int structured_threshold = 1500;
    /// The structured form's bound: the receptances and the preconditioner, about 160 (H + 1) n_s^2
    /// bytes, at most this many (memory bounded for every allowed input).
    static constexpr double max_structured_bytes = 6e9;
    /// Validates the system; throws InvalidInput for bad options or an unsupported law, for
    /// `condensed` on a system whose static stiffness K is singular (a rigid-body mode) or that
    /// has no contact, and for more than max_unknowns unknowns (contacts' relative motions and
    /// internal states, or every DOF in the full formulation, times 2H + 1).
    HarmonicBalance(System system, HarmonicBalanceOptions options);
    /// Every check the constructor makes, and the same InvalidInput, without building the
    /// Fourier matrices (N_t x (2H + 1) each: 420 MB at H = 200, N_t = 65536): for a dry run.
    /// It factorises the static problem once (the condensed formulation's choice).
    static void validate(System system, HarmonicBalanceOptions options);
    /// The largest H <= `wanted` whose unknowns fit max_unknowns for `system` with `options`
    /// (their harmonics ignored): `wanted` itself where the structured Jacobian would carry the
    /// unknowns (options.jacobian automatic or structured, condensed, every harmonic);
    /// below the excitation harmonic h where not even H = h fits. Builds the formulation once
    /// at H = h (the condensed formulation factorises the static problem). Throws what the
    /// constructor throws for the system.
    static int fitting_harmonics(const System& system, HarmonicBalanceOptions options, int wanted);

    const System& system() const { return system_; }
    /// The formulation in use (never automatic).
    Formulation formulation() const { return condensed_ ? Formulation::condensed : Formulation::full; }
    HarmonicBalanceOptions options() const {
        return {harmonics(), time_samples(), formulation(), modes_, odd_,
                structured_ ? JacobianForm::structured : JacobianForm::dense};
    }
    /// True when dR/dX is kept in its structure (JacobianForm::structured).
    bool structured() const { return structured_; }
    /// True when only the odd harmonics are balanced (HarmonicBalanceOptions::odd_harmonics).
    bool odd_harmonics() const { return odd_; }
    /// True for a sector model (System::cyclic, cyclic.hpp) in the full formulation: the unknowns
    /// are the harmonics of the independent DOFs (and the laws' states); every DOF's, the
    /// dependent ones turned by k phi per harmonic, are all_harmonics' (dofs(), relative(), ...),
    /// and the residual is the independent DOFs' rows of the wheel (the dependent rows folded onto
    /// their masters). A sector in the condensed formulation (asked for: automatic chooses full)
    /// has its contacts' signals as unknowns like any model, its receptance solving the own DOFs'
    /// equations per harmonic (Receptance::set_cyclic); cyclic() is false then.
    bool cyclic() const { return cyclic_; }
    /// A sector: P, every signal's coefficients (the layout of all DOFs and states) from the
    /// unknowns, X = P U (the residual is P^T R_X, its Jacobian P^T J_X P); empty otherwise.
    const Eigen::SparseMatrix<double>& cyclic_map() const { return cyclic_map_; }
    /// Modes of the modal receptance in use (0: the direct solve).
    int modes() const { return modes_; }
    /// The contacts' static state under the system's static load and preloads (static_state.hpp),
    /// solved once by the constructor; null when the system has neither (has_static_problem).
    /// Harmonic 0's first guess when solved.
    const StaticState* rest_state() const { return rest_ ? &*rest_ : nullptr; }
    int harmonics() const { return harmonics_; }
    int time_samples() const { return time_samples_; }
    /// Re-plans the AFT on `time_samples` samples (Fourier::check's range); the unknowns and
    /// their layout do not change, so solutions stay valid starts.
    void set_time_samples(int time_samples);
    /// The largest N_t any contact's law needs at the solution x (FrictionModel::
    /// time_samples_needed; 0 where none needs more than the harmonics'), and in `reason` (if
    /// given) which contact needs it and why.
    double time_samples_needed(const Eigen::VectorXd& x, double omega, std::string* reason = nullptr);
    /// 2H + 1: the coefficients of one signal as relative(), state() and dofs() return them (in
    /// fourier.hpp's layout; with odd harmonics only, the constant and the even ones are zero).
    int coefficients() const { return 2 * harmonics_ + 1; }
    /// The coefficients of one signal among the unknowns x: 2H + 1, or with odd harmonics only
    /// 2 ceil(H / 2) (c_1, s_1, c_3, s_3, ...).
    int balanced_coefficients() const { return static_cast<int>(balanced_.size()); }
    /// h: the harmonic that carries the force F cos(h omega t) (System::excitation_harmonic).
    int load_harmonic() const { return system_.excitation_harmonic; }
    int unknowns() const { return unknowns_; }
    Fourier& fourier() { return *fourier_; }

    /// R(X, omega); with non-null pointers also dR/dX (unknowns x unknowns) and dR/domega.
    /// Condensed, where some Z_k is singular at omega (an undamped resonance hit exactly) the
    /// residual is NaN and structure_failure() says why.
    void evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                  Eigen::MatrixXd* jacobian = nullptr, Eigen::VectorXd* jacobian_omega = nullptr);
    /// The same with dR/dX in its structure (structured() only; throws otherwise).
    void evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual, StructuredJacobian& jacobian,
                  Eigen::VectorXd* jacobian_omega);
    /// Why the last evaluation could not solve the linear structure (empty when it could).
    const std::string& structure_failure() const { return structure_failure_; }

    /// Coefficients of every DOF, a (2H+1) x N matrix (column i: DOF i). Condensed, they are
    /// recovered from the contact forces at omega (NaN where Z_k is singular there).
    Eigen::MatrixXd dofs(const Eigen::VectorXd& x, double omega);
    /// An upper bound of max_i max_t |y_i(t)|: max_i (|c0_i| + sum_k |Y_k,i|) from dofs(); with
    /// the modal receptance a looser bound from the modal coordinates (receptance.hpp), whose
    /// cost does not grow with N. +infinity where the structure is singular.
    double amplitude_bound(const Eigen::VectorXd& x, double omega);
    /// Coefficients of the relative displacement q_c of contact c (a contact with several
    /// directions, System::contact_directions: each direction's, stacked), and of its internal
    /// state (empty for memoryless laws).
    Eigen::VectorXd relative(const Eigen::VectorXd& x, int contact) const;
    Eigen::VectorXd state(const Eigen::VectorXd& x, int contact) const;
    /// Friction force samples of contact c on the AFT time grid (several directions: stacked,
    /// contact_force.hpp).
    Eigen::VectorXd force_samples(const Eigen::VectorXd& x, double omega, int contact);
    /// Stick indicator of contact c on the AFT time grid (sticks where < 0; contact_force.hpp).
    Eigen::VectorXd stick_indicator(const Eigen::VectorXd& x, double omega, int contact);

    /// A starting point at omega: the linear response with each Dahl/LuGre contact replaced by
    /// its pre-sliding spring and damper (z = q), each Jenkins contact by its spring k_t, each regularised Coulomb contact by its
    /// slope at zero velocity (a damper F_c / eps), and each exact Coulomb contact held rigid
    /// (q = 0; its force is the constraint's multiplier: the exact permanent-stick solution).
    /// With `sliding`, the slipping limit instead: every contact removed (friction forces
    /// start at their limit, in phase with the relative velocity).
    Eigen::VectorXd linear_guess(double omega, bool sliding = false) const;
    /// Unknowns of a solution with `low_harmonics` <= H harmonics (same system, formulation and
    /// harmonic set) in this layout: every signal's harmonics above low_harmonics are zero.
    Eigen::VectorXd embed_harmonics(const Eigen::VectorXd& low, int low_harmonics) const;
    /// Force scale against which residuals are judged: the excitation amplitude |F|_inf.
    double force_scale() const { return force_scale_; }
    /// Scale of the unknowns x for the corrector and the arclength: max |x_i|, bounded below.
    /// Full: by |F|_inf / max_i K_ii (a displacement; the DOFs' amplitudes grow with the
    /// response). Condensed: by
    /// 1e-3 force_scale max_c G_0,cc (a static contact deflection), so that the relative
    /// displacements, which stay small while the structure resonates around a stuck contact,
    /// still pace the steps.
    double unknown_scale(const Eigen::VectorXd& x) const;

    /// Nonlinear modes (modes.hpp), condensed formulation: from now on the free structure with
    /// the extra damping -xi M, i.e. the excitation F cos(h w t) dropped (the static load and
    /// preloads kept) and C replaced by C - xi M in every receptance (Receptance::
    /// set_mass_damping); residual, dofs(), contact_response() follow. Throws InvalidInput in the full
    /// formulation (modes.hpp adds -xi w (D1 Y) M itself) and for odd harmonics only.
    void set_free_motion(double xi);
    /// Holds (or frees) every contact's switch between residual forms (FrictionModel::
    /// hold_switch): the corrector holds them for one solve. Returns whether any contact has one.
    bool hold_switches(bool on);
    /// Condensed (every harmonic): the contacts' forces minus the shift's springs and dampers at
    /// harmonic k >= 1, Lambda'_k (one per signal, complex c - i s), and with `d_x` their
    /// derivatives in the unknowns (signals x unknowns): what dofs() applies the shifted
    /// receptance to, Y_k = -contact_response(k) Lambda'_k for a free motion (set_free_motion).
    Eigen::VectorXcd shifted_force_harmonic(const Eigen::VectorXd& x, double omega, int k, Eigen::MatrixXcd* d_x = nullptr);
    /// Condensed: Z'_k^-1 W (N x signals, complex), the shifted structure's (C - xi M after
    /// set_free_motion) response to unit forces along the contacts at harmonic k >= 1; one solve
    /// with the N-long solution (cost linear in N); empty where Z'_k is singular.
    Eigen::MatrixXcd contact_response(int k, double omega);
    /// Condensed, after set_free_motion: Y_k = -Z'_k^-1 W Lambda (N, complex), i.e.
    /// -contact_response(k, omega) Lambda, without forming the N x signals matrix when the
    /// receptance is modal (O(N (m + signals)) instead of O(N signals^2)). Empty where Z'_k is
    /// singular.
    Eigen::VectorXcd free_response(int k, double omega, const Eigen::VectorXcd& lambda);
    /// Condensed, after set_free_motion: the derivative in xi of evaluate's residual at
    /// (x, omega), exact: the contacts' rows S_k (dG_k/dxi f_k) (the free motion's rows scale
    /// does not depend on xi), the internal states' rows 0. False where the receptance cannot
    /// give dG_k/dxi (Receptance::apply_mass_damping): difference the residual in xi then.
    bool free_motion_xi_derivative(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& d_xi);

    /// Counters accumulated since construction or the last reset_statistics().
    const EvaluationStatistics& statistics() const { return statistics_; }
    void reset_statistics() { statistics_ = EvaluationStatistics{}; }

private:
    /// Harmonic k > 0 is left out (odd harmonics only, k even): its receptance is never formed.
    bool skipped(int k) const { return odd_ && k > 0 && k % 2 == 0; }
    /// Harmonic k carries the load (k = h and not set_free_motion).
    bool carries_load(int k) const { return !free_ && k == load_harmonic(); }
    /// x in the layout of every harmonic 0..H (signals of 2H + 1 coefficients), from the
    /// unknowns (the same vector unless odd_).
    Eigen::VectorXd all_harmonics(const Eigen::VectorXd& x) const;
    /// relative() and state() of a vector in the layout of every harmonic.
    Eigen::VectorXd relative_all(const Eigen::VectorXd& x, int contact) const;
    Eigen::VectorXd state_all(const Eigen::VectorXd& x, int contact) const;
    void evaluate_all(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual, Eigen::MatrixXd* jacobian,
                      Eigen::VectorXd* jacobian_omega);
    void evaluate_full(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual, Eigen::MatrixXd* jacobian,
                       Eigen::VectorXd* jacobian_omega);
    void evaluate_condensed(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                            Eigen::MatrixXd* jacobian, Eigen::VectorXd* jacobian_omega);
    /// The condensed residual with the receptances applied to all contacts at once (one
    /// complex matrix-vector product per harmonic); the contacts' blocks into `jacobian`.
    void evaluate_structured(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                             StructuredJacobian* jacobian, Eigen::VectorXd* jacobian_omega);
    /// Contact c's law evaluated on x (every harmonic's layout) at omega, minus its shift
    /// (shift_force), into scratch_ (with its Jacobians when `jacobian`).
    FrictionEvaluation& evaluate_contact(const Eigen::VectorXd& x, double omega, int c, bool jacobian);
    /// Every contact's force minus its shift (below), coefficients (2H+1) x signals (condensed).
    Eigen::MatrixXd shifted_forces(const Eigen::VectorXd& x, double omega);
    /// Contact c's force minus the springs and dampers of the shifted structure along its
    /// directions (constructor).
    void shift_force(int c, double omega, const Eigen::VectorXd& q, FrictionEvaluation& e, bool jacobian) const;
    /// The receptance of harmonics 0..H at omega (cached for the last omega); false when a
    /// Z_k is singular there (structure_failure_ says which).
    bool prepare_receptance(double omega);
    /// out += Gr_cd in, for the real form Gr of G_k between signals c and d (`omega_derivative`:
    /// of dG_k/domega).
    void add_receptance(int c, int d, const Eigen::Ref<const Eigen::MatrixXd>& in, Eigen::Ref<Eigen::MatrixXd> out,
                        bool omega_derivative = false) const;

    /// The constructor; without `build_fourier` (validate) fourier_ stays null.
    HarmonicBalance(System system, const HarmonicBalanceOptions& options, bool build_fourier);

    System system_;
    int harmonics_ = 0, time_samples_ = 0;
    std::unique_ptr<Fourier> fourier_;
    bool condensed_ = false;
    bool structured_ = false;
    bool structurable_ = false;  // the structured Jacobian could apply (condensed, every harmonic)
    std::unique_ptr<Receptance> receptance_;
    // per k = 0..H at receptance_omega_; shared with the structured Jacobians built from it
    // (copied on write when a new omega finds it shared)
    std::shared_ptr<std::vector<Receptance::Harmonic>> harmonic_;
    double receptance_omega_ = -1.0;
    Eigen::VectorXd static_flexibility_;          // G_0,aa per signal a
    Eigen::VectorXd shift_stiffness_, shift_damping_;  // kappa_a, delta_a per signal
    // The static load (System::static_load), condensed: W^T K'^-1 F_s per signal (harmonic 0's
    // motion without friction) and K'^-1 F_s (the DOFs' part of it), K' the shifted stiffness;
    // empty without a static load.
    Eigen::VectorXd static_contact_, static_deflection_;
    std::optional<StaticState> rest_;  // rest_state()
    Eigen::MatrixXd row_scale_, row_scale_omega_; // 1 / |G_k,aa| and its omega-derivative ((H+1) x signals)
    std::string structure_failure_;
    std::vector<std::unique_ptr<FrictionModel>> models_;
    std::vector<int> state_offset_;  // start of each contact's state block, -1 if none
    std::vector<int> state_count_;   // its state signals (FrictionModel::state_signals), n coefficients each
    // The signals: one relative displacement each, w_a^T y, contact c's directions being the
    // signals signal_first_[c] .. + signal_count_[c] - 1 (System::contact_directions).
    std::vector<Eigen::VectorXd> directions_;  // w_a, per signal
    std::vector<int> signal_first_, signal_count_;  // per contact
    int signals_ = 0;
    int unknowns_ = 0;      // the corrector's unknowns: signals x balanced_coefficients()
    int all_unknowns_ = 0;  // signals x (2H + 1): the layout of every harmonic
    bool odd_ = false;
    bool cyclic_ = false;
    // cyclic_: all_unknowns_ x unknowns_, the unknowns to every DOF's harmonics (identity rows
    // for the independent DOFs and the states, turns by k phi for the dependent DOFs)
    Eigen::SparseMatrix<double> cyclic_map_;
    bool free_ = false;  // set_free_motion
    std::vector<int> balanced_;        // per signal: the balanced positions among 0..2H
    std::vector<int> balanced_index_;  // over all unknowns: the position in the all-harmonic layout
    Eigen::VectorXd all_residual_, all_jacobian_omega_;  // evaluate's buffers (odd_ only)
    Eigen::MatrixXd all_jacobian_;
    double force_scale_ = 1.0;
    double full_displacement_scale_ = 1.0;
    int modes_ = 0;  ///< |F| / max K_ii (unknown_scale, full formulation)
    FrictionEvaluation scratch_;
    Eigen::MatrixXd forces_, forces_omega_;  // evaluate_structured's n x n_s buffers
    EvaluationStatistics statistics_;
};

}  // namespace hbf
