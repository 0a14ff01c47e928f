// hbfriction — nonlinear modes of friction-damped structures: the extended periodic motion
// concept (EPMC; Krack 2015, Computers & Structures 154), backbone and modal damping.
//
// A nonlinear mode at modal amplitude a is the periodic motion of the unforced structure with
// an artificial damping xi that makes it periodic,
//
//     M y'' + (C - xi M) y' + K y + sum_c w_c f_c = F_s        (no excitation F cos),
//
// xi > 0 feeding in per cycle what C and the contacts dissipate. Harmonic balance (full
// formulation, harmonic_balance.hpp) gives its residual R(X, omega) - xi omega (D1 Y) M; the
// unknowns are the harmonics X, the frequency omega and xi (condensed formulation: the
// contacts' relative displacements Q, the structure C - xi M solved per harmonic by the
// receptance, HarmonicBalance::set_free_motion), and two more equations fix the
// amplitude (Krack's normalisation: the M-norm of the first harmonic) and the phase (by the
// modal coordinate q(t) = phi^T M y(t), phi the chosen linear mode of the stuck structure,
// M-normalised: stuck_modes below):
//
//     sqrt(c1^T M c1 + s1^T M s1) = a,    phi^T M s1 = 0     (y's harmonic 1: c1 cos + s1 sin).
//
// Condensed, y's first harmonic is recovered from the contacts' forces, Y_1 = -Z'_1^-1 W
// Lambda'_1 (HarmonicBalance::contact_response, shifted_force_harmonic), so both rows need one
// solve of harmonic 1 with the N-long solution (cost linear in N); the structure's rows are
// those of the condensed FRF (independent of N with the modal receptance).
// In the linear limit y = a phi cos(theta): a is the modal coordinate's amplitude. Where the
// motion changes shape (a contact releasing another mode) a stays the size of the whole first
// harmonic, not its projection on phi.
// Solved by Newton's method (dense LU, exact derivatives; condensed: the derivatives in xi, and
// those of the two rows in omega, by central differences: the residual is analytic in both at
// fixed X), followed from a_min to a_max by
// pseudo-arclength continuation in (X / (a |phi|), omega / w0, xi / w0, log10 a) (the backbone
// may turn back in a where a contact releases a second mode), with step control.
// Modal damping ratio zeta = xi / (2 omega): the viscous damping ratio of a linear mode that
// dissipates what the nonlinear one does at the same amplitude and frequency when the motion is
// a single harmonic. The energy definition zeta_E = E / (2 pi omega^2 a^2), E the energy C and
// the contacts dissipate per cycle, equals it for a single-harmonic q; with higher harmonics
// the two differ (both reported).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

#include "hbf/continuation.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/model.hpp"
#include "hbf/table.hpp"
#include "hbf/verdict.hpp"

namespace hbf {

/// A linear mode of the stuck structure: M, K' = K + sum k w w^T and C' = C + sum d w w^T over
/// every contact direction's stuck element (static_state.hpp: stuck_elements), the rigid ones
/// (exact Coulomb) as constraints w^T y = 0.
struct LinearMode {
    int index = 0;          ///< 1-based, by ascending frequency
    double omega = 0;       ///< undamped natural frequency sqrt(lambda)
    /// phi^T C' phi / (2 omega): the mode's damping ratio when C' is diagonal in the stuck modes
    /// (then omega = |s| and zeta = -Re s / |s| for the damped eigenvalue s), a first-order
    /// estimate otherwise.
    double zeta = 0;
    Eigen::VectorXd shape;  ///< phi, M-normalised (phi^T M phi = 1), N entries
    /// A sector model's mode (cyclic.hpp: sector_modes at the engine order's phase) is a
    /// travelling wave, complex: phi = shape + i shape_imag on every DOF of the sector, phi^H M
    /// phi = 1. Empty for a structure that is not a sector.
    Eigen::VectorXd shape_imag;
};

/// The stuck structure's modes by ascending frequency; rigid-body modes (omega below 1e-6 of
/// the highest) are included with omega = 0. Throws InvalidInput where neither the constrained
/// M nor K' is positive definite, or every DOF is constrained.
std::vector<LinearMode> stuck_modes(const System& system);

/// The linear limit of the nonlinear mode where the stuck structure is damped (C' = C + the
/// stuck elements' dampers, e.g. regularised Coulomb's F_c / eps): omega, xi and the complex
/// shape psi with (K' - omega^2 M + i omega (C' - xi M)) psi = 0, the motion y = Re(a psi
/// e^{i theta}) being the EPMC's solution as a -> 0. psi continues the undamped `mode` (the
/// oscillating damped mode of largest MAC with it, at least 0.5); M-normalised, phi^T M psi > 0.
/// Found by the secant method in xi on the state-space eigenvalue's real part. ok = false (and
/// `why`) with a rigid stuck contact, a singular M, more than damped_linear_mode_dofs DOFs, or
/// no oscillating damped mode like `mode`.
struct DampedLinearMode {
    bool ok = false;
    std::string why;
    double omega = 0, xi = 0;
    double mac = 0;  ///< with the undamped mode
    Eigen::VectorXcd shape;
};
constexpr int damped_linear_mode_dofs = 200;
DampedLinearMode damped_linear_mode(const System& system, const LinearMode& mode);

/// Where a stuck mode starts to slip: the largest modal amplitude a* at which a stuck periodic
/// motion y = y_m + a Re(phi e^{i theta}) exists, and the range of a a backbone without a given
/// range follows, from a tenth of a* (the contacts well inside stick) to a hundred times it
/// (slipping over most of the period). The mode's forces are the stuck elements' (static_state.hpp:
/// stuck_elements): a spring's (k_c + i omega d_c) w^T phi, a rigid contact's the constraint
/// force that holds it, lambda = -(W^T W)^-1 W^T (K' - omega^2 M) phi over the rigid directions
/// W (damping left out). A stuck motion leaves each contact's slider anywhere, and the sliders'
/// places set the mean state y_m: every contact's mean forces (T_m, and for a contact with a
/// normal direction N_m) are the static state's (static_state.hpp) plus S s, s the slider places
/// and S the stuck structure's static response to them (a tangential mean force moves the normal
/// ones through the structure). A contact stays stuck while |T_m + a Re(f_T e^{i theta})| <=
/// friction_limit, or <= mu (N_m + a Re(f_N e^{i theta})) for one with a normal direction, at
/// every phase theta (two phases, 0 and pi, where every force is in phase, as for an undamped
/// real mode: the condition is convex in cos theta; else 64). a* is the largest a for which
/// some s keeps every contact stuck: a second-order cone programme in (s, a), solved by a barrier
/// method to about 1e-10 relative; the contact whose condition binds there slips, or opens where
/// its normal force reaches 0 first (`opens`). Above a* every periodic motion slips somewhere;
/// below it a motion whose sliders sit elsewhere may already slip: with the sliders where the
/// static load leaves them (s = 0) the first contact reaches its limit at static_amplitude <= a*
/// (harmonic balance centres each stuck contact's mean force on its own, so a backbone with
/// several contacts departs between the two). Without a contact with a normal direction, each
/// friction-limit contact's mean is free and a* = min friction_limit / |f|. found = false, and
/// `why`, where no contact with a friction limit is moved by the mode (force elements alone, a
/// mode that leaves every contact at rest, contacts open at rest, a static state not solved).
struct SlipOnset {
    bool found = false;
    std::string why;
    double amplitude = 0;  ///< a*: no stuck periodic motion above it
    int contact = -1;      ///< 0-based: the contact that slips (or opens) at a*
    bool opens = false;    ///< that contact opens at a* (its normal force reaches 0)
    double static_amplitude = 0;  ///< the first contact's limit with the sliders at their static places
    int static_contact = -1;      ///< 0-based: that contact
    int mode = 0;                 ///< the stuck mode's index (LinearMode::index, 1-based)
    double amplitude_min = 0, amplitude_max = 0;  ///< a* / 10, 100 a*
};
SlipOnset slip_onset(const System& system, const LinearMode& mode);

struct ModeOptions {
    /// The linear mode followed: 1-based index among stuck_modes (near_frequency = 0), or the
    /// one nearest near_frequency (> 0).
    int mode = 1;
    double near_frequency = 0;
    /// Range of the modal amplitude a (the first harmonic's M-norm, top of this file), 0 < a_min < a_max.
    double amplitude_min = 1e-4, amplitude_max = 1.0;
    /// The first point's frequency guess at a_min (> 0), instead of the automatic start (0):
    /// the linear limit's, and where a_min is beyond the linear regime the backbone followed up
    /// to a_min from it (NonlinearModes::follow). A given start is the user's: the backbone
    /// says it was not checked against the linear limit.
    double start_frequency = 0;
    /// Arclength steps in the scaled coordinates (log10 a counts in decades): the first, the
    /// largest (initial_step..1) and the smallest (below it the continuation stops).
    double initial_step = 0.05;
    double max_step = 0.1;
    double min_step = 1e-6;
    /// A step is retried with half the length where omega changes by more than this (relative).
    double max_omega_change = 0.02;
    int max_points = 2000;       ///< point budget
    int max_iterations = 30;     ///< Newton iterations per point
    /// Accept when max |residual| <= tolerance: the structure's rows relative to the mode's
    /// inertial force a omega_0^2 |M phi|_inf, the amplitude and phase rows relative to a.
    double tolerance = 1e-10;
    /// Called after each accepted point with its amplitude and the number of points; must not throw.
    std::function<void(double amplitude, int points)> progress;
    /// Asked before every step (and in the run-up from the linear regime to a_min): a non-empty
    /// answer (why: an interrupt, a time limit) ends the backbone there with status stopped and
    /// the answer in its message; the points so far are kept. Empty: never.
    std::function<std::string()> stop;
    /// Throws InvalidInput naming the first field out of range.
    void validate() const;
};
/// The slip onset of the stuck mode `options` chooses (ModeOptions::mode or near_frequency; its
/// amplitude range is not used), for harmonic balance `hbo`: the range a backbone follows when
/// none is given (hbf modes, Python's modes()). Throws InvalidInput as NonlinearModes does for a
/// mode out of range.
SlipOnset slip_onset(const System& system, const HarmonicBalanceOptions& hbo, const ModeOptions& options);


/// One point of the backbone: the harmonics x (HarmonicBalance's full layout), omega and xi at
/// modal amplitude a.
struct ModePoint {
    double amplitude = 0;
    double omega = 0;
    double xi = 0;
    Eigen::VectorXd x;
    int iterations = 0;     ///< Newton iterations
    double residual = 0;    ///< max |scaled residual| (ModeOptions::tolerance)
    double step = 0;        ///< step in log10 a that led here (0 for the first point)
    double zeta() const { return xi / (2.0 * omega); }
};

/// completed: a_min to a_max; left_range: the backbone turned back below a_min; min_step: a
/// step failed at the smallest length; point_budget; start_failed: the first point (a_min) did
/// not converge; stopped: ModeOptions::stop asked it to end.
enum class ModeStatus { completed, left_range, min_step, point_budget, start_failed, stopped };
std::string to_string(ModeStatus status);

struct Backbone {
    LinearMode linear;              ///< the mode followed
    std::vector<ModePoint> points;  ///< by increasing amplitude
    ModeStatus status = ModeStatus::completed;
    std::string message;            ///< where and why it stopped (empty when completed)
    int failed_steps = 0;           ///< steps retried with half the length
    int corners = 0;                ///< turns sharper than 0.3 rad crossed (stick/slip switches: the
                                    ///< turn did not shrink with the step, or at a step <= 1e-4)
    long long evaluations = 0;      ///< residual and Jacobian evaluations
    double seconds = 0;
    /// How the first point was reached (NonlinearModes::follow): "linear" (a_min is in the
    /// linear regime: the first point equals the linear limit's continuation), "run-up" (followed
    /// from the linear regime up to a_min), "given" (ModeOptions::start_frequency), or
    /// "unchecked" (the linear regime not reached below a_min: the first point may belong to
    /// another solution; a warning).
    std::string start;
    std::string start_note;  ///< what the start found (a solution other than the backbone's, ...)
    /// The linear limit the backbone starts from: the undamped stuck mode's omega and its xi
    /// estimate, or the damped linear mode's (damped_linear_mode) where the stuck structure is
    /// damped.
    double linear_omega = 0, linear_xi = 0;
    bool damped_linear = false;  ///< the linear limit is damped_linear_mode's
};

/// Quantities of one backbone point (ModeMetrics::of).
struct ModeMetrics {
    double zeta = 0;            ///< xi / (2 omega)
    double zeta_energy = 0;     ///< (E_friction + E_viscous) / (2 pi omega^2 a^2)
    double friction_energy = 0; ///< dissipated per cycle by the contacts (AFT grid; as hbf frf's energy)
    double viscous_energy = 0;  ///< dissipated per cycle by C
    /// Fed in per cycle by -xi M y': xi pi omega sum_k k^2 (c_k^T M c_k + s_k^T M s_k).
    double injected_energy = 0;
    /// |injected - viscous - friction| / max(injected, viscous + |friction|, 1e-8 2 pi omega^2
    /// a^2): the energy balance of the solution. The floor: a damping ratio below 1e-8 is
    /// measured absolutely (the friction energy of a stuck contact on the AFT grid is rounding,
    /// 1e-17 of 2 pi omega^2 a^2, with either sign).
    double energy_error = 0;
    /// Per harmonic k = 0..H: sqrt(Y_k^T M Y_k) (both coefficients) over the M-norm of all
    /// harmonics: the mode shape's harmonic content.
    std::vector<double> harmonic_content;
    std::vector<ContactRegime> contacts;  ///< stick and separated shares per contact
    std::vector<double> output_max;       ///< per output: max over one period of |o(t)|
    std::vector<double> output_amp1;      ///< per output: first-harmonic amplitude
};

/// One point of a forced response synthesised from a nonlinear mode (single-nonlinear-mode
/// synthesis, Krack et al. 2014): the structure moves in the mode's shape at amplitude a, and
/// the mode's own equation with the EPMC damping,
///     (w(a)^2 - Omega^2 + i Omega xi(a)) a = psi^H F,   psi = (c1 - i s1) / a  (psi^H M psi = 1),
/// is solved for the excitation frequency Omega: |psi^H F|^2 / a^2 = (w^2 - Omega^2)^2 +
/// Omega^2 xi^2, a quadratic in Omega^2 with up to two positive roots (the two flanks of the
/// resonance; none where a exceeds what F can sustain). Valid near the resonance of a mode
/// well separated from the others; friction's rate-independent dissipation is taken at the
/// mode's own frequency (viscous in Omega), exact at the phase resonance Omega = w(a).
struct SynthesisPoint {
    double omega = 0;      ///< excitation frequency Omega
    double amplitude = 0;  ///< the backbone point's modal amplitude a
    double mode_omega = 0; ///< the backbone point's frequency w(a) (Omega = w(a): phase resonance)
    int flank = 0;         ///< -1 the root below the backbone's w^2 - xi^2 / 2, +1 the one above
    std::vector<double> output_amp1;  ///< each output's first-harmonic amplitude (the mode's at a)
};

/// A backbone point checked by the event-exact solver (event_exact.hpp: exact_flow). The EPMC
/// orbit is a periodic free motion of the structure with damping C - xi M: for exact Coulomb
/// and Jenkins contacts the same linear flows and friction events as the forced exact orbits.
/// Newton shooting on (y(0), y'(0), omega, xi): one period's flow returns to its start, and the
/// modal coordinate q = phi^T M y has at t = 0 the value and velocity of the harmonic-balance
/// orbit at the section theta0 (the middle of its longest stretch where every contact slips):
/// both orbits are compared at the same modal displacement and velocity there, a functional of
/// the orbit that converges with H, not at the same a (the first harmonic's M-norm, which the
/// flow does not give). The monodromy is exact, the derivatives in omega and xi central
/// differences of the flow.
struct ExactModeCheck {
    bool checked = false;   ///< false: not applicable or not converged (message says why)
    std::string message;
    double omega = 0, xi = 0;  ///< the exact orbit's
    double gap = 0;            ///< max(|omega - omega_HB|, |xi - xi_HB|) / omega (checked only)
    int iterations = 0;
    double residual = 0;       ///< |P(z) - z| relative to |z| (velocities divided by omega)
};

/// The EPMC problem of one mode (see the top of this file).
class NonlinearModes {
public:
    /// `system` with its excitation ignored; `hbo`'s formulation full, condensed (with its
    /// modes: the modal receptance) or automatic (mode_harmonic_balance); odd_harmonics is not
    /// allowed (the modal motion may have a mean). Throws InvalidInput for bad options, a mode
    /// out of range (naming the range), a rigid-body mode, condensed where HarmonicBalance
    /// refuses it (K singular).
    NonlinearModes(System system, const HarmonicBalanceOptions& hbo, const ModeOptions& options);

    const LinearMode& linear() const { return linear_; }
    /// The formulation in use (full or condensed).
    Formulation formulation() const { return hb_->formulation(); }
    /// Coefficients of every DOF at a point ((2H+1) x N; condensed: recovered from the contact
    /// forces of the free structure with its xi).
    Eigen::MatrixXd motion(const ModePoint& point);
    HarmonicBalance& harmonic_balance() { return *hb_; }
    const ModeOptions& options() const { return options_; }

    /// The scaled residual (size unknowns + 2) at (x, omega, xi) for amplitude a, and with a
    /// non-null pointer its Jacobian with respect to (x, omega, xi).
    void residual(const Eigen::VectorXd& x, double omega, double xi, double amplitude, Eigen::VectorXd& r,
                  Eigen::MatrixXd* jacobian = nullptr);
    /// Newton from `point` (its x, omega, xi the guess) at point.amplitude; true when the
    /// tolerance is met (point holds the result, iterations and residual).
    bool solve(ModePoint& point);
    /// The unit tangent of the backbone at a solution in the scaled coordinates (x / (a
    /// |phi|_inf), internal states by their size, omega / w0, xi / w0, log10 a) (size unknowns
    /// + 3), oriented along `previous`.
    Eigen::VectorXd tangent(const ModePoint& point, const Eigen::VectorXd& previous);
    /// The linear mode's motion at amplitude a: y = a phi cos(theta) (with the static state on
    /// harmonic 0), omega and xi of the linear mode: the first guess; where the stuck structure
    /// is damped, the damped linear mode's y = Re(a psi e^{i theta}), omega and xi.
    ModePoint linear_guess(double amplitude);
    /// The damped linear mode (ok = false where the undamped mode is the start).
    const DampedLinearMode& damped_linear() const { return damped_; }
    /// Follows the mode from a_min to a_max.
    Backbone follow();

    /// The point against the event-exact solver (ExactModeCheck): every contact exact Coulomb
    /// or Jenkins along one direction, M positive definite, at most exact_solver_max_dofs DOFs,
    /// and some contact slipping somewhere in the period (permanent stick is the linear mode);
    /// otherwise checked = false with the reason.
    ExactModeCheck exact_check(const ModePoint& point);
    /// Metrics of a point; `outputs` as hbf frf's (validated against the system).
    ModeMetrics metrics(const ModePoint& point, const std::vector<Output>& outputs = {});
    /// The synthesised response to F cos(Omega t) (F: N entries; SynthesisPoint) from a backbone
    /// of this mode and its points' metrics (their output_amp1, of `outputs`): the lower flank by
    /// increasing a, then the upper by decreasing a. The largest amplitude F sustains (the
    /// synthesised peak, where the two flanks meet) is located between the backbone's points by
    /// bisection in a, solving the mode there. Throws InvalidInput for F of the wrong size.
    std::vector<SynthesisPoint> synthesize(const Backbone& backbone, const std::vector<ModeMetrics>& metrics,
                                           const Eigen::VectorXd& force, const std::vector<Output>& outputs = {});

private:
    std::vector<double> metrics_of(const ModePoint& point, const std::vector<Output>& outputs);
    /// Newton on G = 0 at fixed amplitude (tangent null), or with log10 a free and the
    /// arclength condition t . (v - predicted) / scale = 0. Where contacts switch between
    /// residual forms (FrictionModel::hold_switch: law unilateral's permanent stick), each form
    /// is held for one Newton solve (decided at the start, then at each solution, at most three
    /// solves) and a solution is accepted only if the residual with the switches free passes,
    /// as the FRF's corrector does.
    bool correct(ModePoint& point, const Eigen::VectorXd* tangent, const Eigen::VectorXd* predicted);
    /// correct()'s Newton, with the switches as they are.
    bool correct_once(ModePoint& point, const Eigen::VectorXd* tangent, const Eigen::VectorXd* predicted);
    /// The continuation loop of follow() from `start` (pushed first) over log10 a in
    /// [log10 a_first, log10 a_last].
    void continue_from(const ModePoint& start, double a_first, double a_last, Backbone& b);
    /// The first point at a_min (follow(): the linear limit, the run-up or the given start);
    /// false (with b's status and message) when none converged.
    bool first_point(ModePoint& start, Backbone& b);
    /// residual() of the condensed formulation.
    void residual_condensed(const Eigen::VectorXd& x, double omega, double xi, double amplitude, Eigen::VectorXd& r,
                            Eigen::MatrixXd* jacobian);
    /// The arclength's coordinate scales at a point: a |phi|_inf for the DOFs, each contact's
    /// internal states by their largest entry (at least a |phi|_inf), w0, w0, 1.
    Eigen::VectorXd column_scale(const ModePoint& point) const;
    System system_;
    ModeOptions options_;
    LinearMode linear_;
    std::unique_ptr<HarmonicBalance> hb_;
    Eigen::VectorXd m_phi_;  // M phi (a sector: M Re phi)
    Eigen::VectorXd m_phi_imag_;  // a sector: M Im phi (the phase row Im(phi^H M Y_1) = 0); else empty
    Eigen::MatrixXd sector_mass_d1_;  // a sector: P^T (M (x) D1) P, the -xi omega term's Jacobian per xi omega
    Eigen::VectorXd guess_shape_;  // the unknowns' harmonic 1 of the linear mode per unit a: phi, or W^T phi (condensed)
    Eigen::VectorXd guess_sine_;   // its sine part (the damped linear mode: -Im psi; else empty)
    DampedLinearMode damped_;
    bool condensed_ = false;
    double force_unit_ = 1;  // omega_0^2 |M phi|_inf (times a: the structure rows' scale)
    double phi_max_ = 1;     // |phi|_inf
    double static_force_ = 0;  // largest static load or preload (the residual's rounding floor)
    long long evaluations_ = 0;
};

/// What the backbone is worth: an error when the first point failed, a warning when it stopped
/// before a_max (its status and message) or a point fails the energy balance (above
/// energy_balance_limit(tolerance)). hbf modes' exit code and Python's status.
Verdict judge_backbone(const Backbone& backbone, const std::vector<ModeMetrics>& metrics, double tolerance);

/// One nonlinear mode as the front ends compute it (hbf modes, Python's modes()): the backbone,
/// its points' metrics, its table, the synthesised response (with `synthesis`) and the verdict.
struct ModeRun {
    Backbone backbone;
    std::vector<ModeMetrics> metrics;
    io::Table table;
    std::vector<SynthesisPoint> synthesis;  ///< the response to system.excitation (with `synthesis`)
    Verdict verdict;
    int harmonics = 0, time_samples = 0;
    Formulation formulation = Formulation::full;  ///< the one used
    int modes = 0;                                ///< condensed: the modal receptance's modes (0: direct)
    std::vector<ExactModeCheck> exact;            ///< per point (with `exact_check`)
};
/// `hbo` as mode_harmonic_balance makes it (NonlinearModes: InvalidInput for odd harmonics);
/// `outputs` empty: every DOF. Throws InvalidInput as
/// NonlinearModes and for `synthesis` on a system whose excitation harmonic is not 1.
/// With `exact_check`, every point against the event-exact solver (NonlinearModes::exact_check),
/// the table's columns exact_w, exact_xi, exact_gap (io::exact_columns) and a note with the
/// largest gap and the points not checked.
ModeRun compute_mode(const System& system, HarmonicBalanceOptions hbo, const ModeOptions& options,
                     std::vector<Output> outputs, bool synthesis, bool exact_check = false);
/// The options the modes use: the dense Jacobian; automatic becomes full where the full
/// formulation has at most mode_full_limit unknowns (N (2H + 1)) and no modes are asked for,
/// else HarmonicBalance's own automatic choice (condensed where K is invertible); full has no modes.
/// The full formulation's dense Newton step costs (N (2H + 1))^3, the condensed one's grows with
/// the contacts' directions: on NLvib's cantilever (N = 38, one spring, H = 10: 798 unknowns)
/// the full backbone takes 60 times the condensed one, to the same points.
HarmonicBalanceOptions mode_harmonic_balance(HarmonicBalanceOptions hbo, const System& system);
constexpr int mode_full_limit = 256;

namespace io {
/// The backbone's columns for `outputs`, `contacts` contacts (`normal`: which have a normal
/// direction: a separated_fraction column) and H harmonics, in order (the CSV header, --help and
/// Python): a, w, xi, zeta, zeta_energy, energy, friction_energy, viscous_energy, energy_error,
/// per output `<name>_max` and `<name>_amp1`, per contact `stick_fraction_c<k>`, `regime_c<k>`
/// [separated_fraction_c<k>], h0..hH (harmonic content), iterations, residual.
std::vector<Column> backbone_columns(const std::vector<Output>& outputs, const std::vector<bool>& normal, int harmonics);
/// The event-exact check's columns (compute_mode with exact_check): exact_w, exact_xi, exact_gap.
std::vector<Column> exact_columns();
/// The synthesised response's columns (hbf modes --synthesis-out, Python): w, a, w_mode, flank
/// and each output's _amp1.
std::vector<Column> synthesis_columns(const std::vector<Output>& outputs);
/// One row per synthesised point.
Table synthesis_table(const std::vector<SynthesisPoint>& curve, const std::vector<Output>& outputs);
/// One row per point (metrics[k] belongs to backbone.points[k]).
Table backbone_table(const Backbone& backbone, const std::vector<ModeMetrics>& metrics,
                     const std::vector<Output>& outputs, const std::vector<bool>& normal, int harmonics);
}  // namespace io

}  // namespace hbf
