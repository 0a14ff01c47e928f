// hbfriction — corrector (Ceres), pseudo-arclength continuation in omega, and the branch data
// with its post-processing.
//
// The continuation follows u = (X, omega) along R(X, omega) = 0. Distances along the branch are
// measured in scaled, dimensionless coordinates (X / x_ref, omega / omega_ref): x_ref = the
// largest unknown at the current point (HarmonicBalance::unknown_scale: at least a small
// displacement of the structure under the force), omega_ref = omega_end (omega_scale), so that
// a problem written in other units gives the same branch. The predictor steps by h along the
// unit tangent t (null vector of [dR/dX x_ref, dR/domega omega_ref], oriented like the
// previous one); the corrector solves the
// square system
//     R(X, omega) / force_scale = 0,   t . (u - u_predicted) = 0
// with Ceres (Levenberg-Marquardt, dense normal Cholesky, analytic Jacobian; see README). A point is accepted only when
// |R|_inf / force_scale <= tolerance — checked by us, since Ceres has no absolute test — or,
// within 1000 times the tolerance, when the residual is within 8 times its own rounding noise
// (measured by moving omega by 16 ulp; the condensed residual near a sharp resonance of a
// large model carries cond(Z_k) times the rounding): counted in noise_limited.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hbf/harmonic_balance.hpp"
#include "hbf/linear_limits.hpp"

namespace hbf {

/// Ceres configurations of the corrector (measured in benchmarks/hb_branch; see README).
enum class TrustRegion { levenberg_marquardt, dogleg };
enum class DenseSolver { qr, normal_cholesky };
enum class DenseLibrary { eigen, lapack };

struct CorrectorOptions {
    int max_iterations = 20;  ///< Ceres iterations per correction
    /// Accept when |R|_inf <= tolerance * force_scale; smallest_tolerance..largest_tolerance
    /// (below 1e-14 the residual's rounding noise decides; above 1e-2 a point is not a solution).
    double tolerance = 1e-9;
    static constexpr double smallest_tolerance = 1e-14, largest_tolerance = 1e-2;
    TrustRegion trust_region = TrustRegion::levenberg_marquardt;  ///< Ceres trust-region strategy
    DenseSolver dense_solver = DenseSolver::normal_cholesky;                 ///< Ceres dense linear solver
    DenseLibrary dense_library = DenseLibrary::eigen;            ///< Ceres dense linear algebra
};

struct ContinuationOptions {
    double omega_start = 0.5;     ///< first frequency (the branch starts here)
    double omega_end = 1.6;       ///< last frequency (the branch stops here)
    /// Frequency scale of the arclength: distances are measured in (X / x_ref, omega /
    /// omega_scale), both dimensionless, so the same physical problem in other units gives
    /// the same branch. 0: omega_end. >= 0.
    double omega_scale = 0;
    double initial_step = 0.01;   ///< first arclength step (scaled coordinates)
    double min_step = 1e-6;       ///< below this the continuation stops with status min_step
    /// The step never grows beyond this; smallest_max_step..largest_max_step (dimensionless:
    /// w / omega_scale and the coefficients relative to the current amplitude).
    double max_step = 1.0;
    static constexpr double smallest_max_step = 1e-5, largest_max_step = 10.0;
    double max_turn = 0.2;        ///< largest angle (rad) between successive tangents; a
                                  ///< sharper turn halves the step and retries
    int max_points = 5000;        ///< point budget per branch
    double max_amplitude = 1e3;   ///< stop when any max_t |y_i(t)| bound exceeds this
    bool locate_transitions = true;  ///< insert the stick-slip transitions of contact 1 (below)
    /// Locate each fold (where the tangent's omega-component changes sign) on the branch and
    /// insert it as the point of kind fold; sign changes without a real turn in omega are not
    /// folds (continue_branch).
    bool locate_folds = true;
    /// Resolve the resonances of the linear structure (linear_resonances, model.hpp: the released,
    /// stuck and rigid-contact limits' natural frequencies in [omega_start, omega_end], computed
    /// before the continuation): a step whose frequency interval contains one is accepted only
    /// when the branch is bounded there, i.e. when the solution at that frequency, solved from
    /// the step's chord, converges below max_amplitude; otherwise the step is halved, so that a
    /// large step never jumps across an unbounded (stuck) resonance: the branch climbs it to the
    /// cap (status amplitude_cap) instead.
    bool resolve_resonances = true;
    bool restart_past_cap = true; ///< after an amplitude cap, start a second branch at omega_end,
                                  ///< and if that caps too, a third in the middle of the gap
                                  ///< between the two caps, followed both ways
    CorrectorOptions corrector;
    /// Called after each accepted branch point with its omega and the number of points so far
    /// (all branches): a progress display. May be empty; it must not throw.
    std::function<void(double omega, int points)> progress;
    /// Called before each marked fold is located (with locate_folds) with the folds done and
    /// their number: locating them can take longer than the branch (a 99-node interface's many
    /// folds at corners). May be empty; it must not throw.
    std::function<void(int done, int total)> fold_progress;
};

/// cap: the last point of a trace stopped by the amplitude cap (an unbounded resonance; a
/// fold there stays a fold). branch_point, period_doubling, neimark_sacker: the first regular
/// point past a change of stability of that kind (stability.hpp: a real multiplier through +1
/// without a turn, through -1, a complex pair), set by the stability analysis.
enum class PointKind { regular, fold, sample, transition, cap, branch_point, period_doubling, neimark_sacker };
/// The regime boundary a transition point lies on (of the contact SolutionPoint::contact).
enum class Boundary { none, stick_stick_slip, stick_slip_slip };
/// "", "stick|stick-slip", "stick-slip|slip".
std::string to_string(Boundary boundary);
struct SolutionPoint;
/// The transition points of `points` per contact (`contacts` entries: SolutionPoint::contact).
std::vector<int> transitions_per_contact(const std::vector<SolutionPoint>& points, int contacts);
/// " (contact 1: a, contact 2: b, ...)" for several contacts; "" for one.
std::string per_contact_counts(const std::vector<int>& counts);
std::string to_string(PointKind kind);

/// One solution: omega, the coefficients X (HarmonicBalance layout) and diagnostics.
struct SolutionPoint {
    double omega = 0;
    Eigen::VectorXd x;
    int iterations = 0;     ///< corrector (Ceres) iterations
    double residual = 0;    ///< |R|_inf / force_scale after correction
    double step = 0;        ///< arclength step that led to this point (0 for the first)
    PointKind kind = PointKind::regular;
    int branch = 1;         ///< 1-based branch number: 1 from omega_start, 2 from omega_end after
                            ///< an amplitude cap, 3 between two caps
    Boundary boundary = Boundary::none;  ///< kind transition: which regimes meet here
    int contact = 0;        ///< kind transition: the contact (0-based) whose regime changes here
};

/// Work counters of a Corrector.
struct CorrectorStatistics {
    long long solves = 0;           ///< Ceres Solve calls (corrections, including failed ones)
    long long iterations = 0;       ///< Ceres iterations (successful and unsuccessful steps)
    double seconds = 0;             ///< wall time inside Ceres' Solve, evaluations included
    double evaluation_seconds = 0;  ///< of which in HarmonicBalance::evaluate
    long long noise_limited = 0;    ///< corrections accepted above the tolerance but within 8
                                    ///< times the residual's own rounding noise (Corrector::correct)
    // The structured Jacobian (HarmonicBalance::structured()): Newton steps by GMRES instead of Ceres.
    long long krylov_iterations = 0;   ///< GMRES products with I + Gr Df (corrections and tangents)
    long long factorizations = 0;      ///< preconditioner factorisations (H + 1 complex LUs each)
    double factorization_seconds = 0;  ///< their time
    double krylov_seconds = 0;         ///< time in GMRES (products and preconditioner solves)
};

/// How a continuation ended. completed: the branch spans [wmin, wmax]; every other status is
/// an incomplete result: amplitude_cap (the response exceeds max_amplitude: an unbounded
/// resonance, capped), left_range (the branch turned back out of the range before spanning
/// it), point_budget (max_points reached), min_step (the corrector stalled), start_failed.
/// With several branches (restarts past a cap) the status is the worst of them, in the order
/// completed < amplitude_cap < left_range < point_budget < min_step < start_failed.
/// Throws InvalidInput naming the first option out of range (continue_branch calls it).
void validate(const ContinuationOptions& options);

enum class ContinuationStatus { completed, amplitude_cap, left_range, point_budget, min_step, start_failed };
std::string to_string(ContinuationStatus status);

struct BranchResult {
    std::vector<SolutionPoint> points;  ///< in branch order; branches 2 and 3 (if any) after branch 1
    ContinuationStatus status = ContinuationStatus::completed;
    std::string message;                ///< where and why it stopped
    int corrections = 0;                ///< corrector calls, including failed ones
    int failed_corrections = 0;
    int transitions = 0;                ///< points of kind transition
    std::vector<int> contact_transitions;  ///< of them, per contact (with locate_transitions)
    int located_folds = 0;              ///< folds located and inserted (kind fold)
    int unconfirmed_folds = 0;          ///< sign changes of the tangent's omega-component that are
                                        ///< not a real turn in omega (noise on a nearly vertical
                                        ///< segment), or whose location failed: not marked
    int rejected_jumps = 0;             ///< steps whose correction exceeded the step (halved)
    /// corners sharper than a right angle crossed by solves at fixed frequencies where the
    /// arclength corrector failed at the minimum step (trace.cpp)
    int crossed_corners = 0;
    int unlocated_transitions = 0;      ///< regime changes between two points whose boundary
                                        ///< could not be located (named in message)
    double coverage = 0;                ///< share of [wmin, wmax] spanned by the branch segments
    /// The linear structure's resonances in [omega_start, omega_end] (resolve_resonances).
    std::vector<LinearResonance> resonances;
    int resonance_rejections = 0;       ///< steps halved for crossing a resonance unresolved
    int unresolved_resonances = 0;      ///< crossings accepted unresolved at the minimum step
                                        ///< (named in message)
    CorrectorStatistics corrector;    ///< Ceres work of the whole continuation
    EvaluationStatistics evaluation;  ///< residual/Jacobian work (corrector and predictor)
    double predictor_seconds = 0;     ///< tangents: their evaluations and LU solves
    double seconds = 0;               ///< wall time of continue_branch
    /// One line: status, points, folds, where it stopped.
    std::string summary() const;
};

/// Corrects u = (x, omega) onto R = 0: with Ceres (dense Jacobian; keeps the Ceres problem
/// between calls), or with the structured Jacobian (HarmonicBalance::structured()) by Newton
/// steps solved by preconditioned GMRES (structured_jacobian.hpp) with a backtracking line
/// search on |R|^2 + (arclength residual)^2, the preconditioner kept between steps and
/// corrections while GMRES converges in few iterations.
class Corrector {
public:
    Corrector(HarmonicBalance& hb, CorrectorOptions options);
    ~Corrector();
    Corrector(const Corrector&) = delete;
    Corrector& operator=(const Corrector&) = delete;
    /// Solves R(x, omega) = 0 together with tangent . (scaled(u) - scaled(u_predicted)) = 0,
    /// scaled(u) = (x / x_scale, omega / omega_scale). `x` and `omega` hold the prediction on
    /// entry and the result on exit. Returns whether the residual tolerance was met;
    /// iterations and residual are reported.
    bool correct(Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent, double x_scale,
                 int& iterations, double& residual, double omega_scale = 1.0);
    /// Solves at fixed omega (tangent = e_omega).
    bool solve_at(Eigen::VectorXd& x, double omega, double x_scale, int& iterations, double& residual);
    /// Counters accumulated over all calls.
    const CorrectorStatistics& statistics() const;
    /// dR/dX and dR/domega at (x, omega) if the last evaluation was made exactly there (as
    /// after a successful correction) and the Jacobian is dense; false otherwise.
    bool cached_jacobian(const Eigen::VectorXd& x, double omega, Eigen::MatrixXd& jacobian,
                         Eigen::VectorXd& jacobian_omega) const;
    /// branch_tangent at (x, omega), from the last evaluation when it was made there (dense or
    /// structured Jacobian; the structured one by GMRES with the corrector's preconditioner).
    Eigen::VectorXd tangent(const Eigen::VectorXd& x, double omega, double x_scale, const Eigen::VectorXd& previous,
                            double omega_scale = 1.0);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Unit tangent of the branch R(x, omega) = 0 at a solution, in the scaled coordinates
/// (x / x_scale, omega / omega_scale): the null vector of [dR/dX x_scale, dR/domega
/// omega_scale], oriented so that its dot product with `previous` (any vector of size
/// unknowns + 1 not orthogonal to it) is > 0.
Eigen::VectorXd branch_tangent(HarmonicBalance& hb, const Eigen::VectorXd& x, double omega, double x_scale,
                               const Eigen::VectorXd& previous, double omega_scale = 1.0);

/// The same from given dR/dX (J) and dR/domega (r_omega) at the point.
Eigen::VectorXd branch_tangent(const Eigen::MatrixXd& J, const Eigen::VectorXd& r_omega, double x_scale,
                               const Eigen::VectorXd& previous, double omega_scale = 1.0);

/// Follows the branch from omega_start to omega_end (see the file comment).
/// Folds (with locate_folds): wherever the tangent's omega-component changes sign between two
/// successive points, the zero of that component (the last unknown of the bordered tangent
/// system, zero exactly where dR/dX is singular) is found by regula falsi along the chord (trial
/// points corrected on the hyperplane normal to it) to 1e-12 of the chord or 1e-10 of
/// arclength, and inserted as the point of kind fold, if omega there is beyond omega at both neighbours by more than 1e-10
/// omega (a real turn); other sign changes are noise and count in unconfirmed_folds.
/// Stick-slip transitions of contact 1 (with locate_transitions): wherever the regime changes
/// between two successive points of a branch, the boundary is located by bisection along the
/// chord between them (each trial point corrected onto the branch on the hyperplane normal to
/// the chord) on the regime of stick_pattern: full stick ends where the first sample
/// slips (max phi crosses 0), full slip where a stick phase appears. Bisection stops when the bracket is below 1e-10
/// in scaled arclength (both ends solved); the point on the stick side (stick|stick-slip) or
/// on the stick-slip side (stick-slip|slip) is inserted as a point of kind transition.
BranchResult continue_branch(HarmonicBalance& hb, const ContinuationOptions& options);

/// Solves exactly at each frequency in `omegas` every solution of the branch there (all of
/// them where it folds), starting from the branch (a failed solve is retried from the nearer
/// branch point with five times the iterations; a frequency within 1e-9 relative of a branch
/// end counts as on the branch); returns points of kind `sample`. The frequencies where no
/// solution was found (outside the branch, or every solve failed) go to `missed`.
std::vector<SolutionPoint> sample_branch(HarmonicBalance& hb, const BranchResult& branch,
                                         const std::vector<double>& omegas, const CorrectorOptions& options,
                                         std::vector<double>* missed = nullptr);

// ---- post-processing -------------------------------------------------------------------

/// Quantities derived from one solution point.
struct PointMetrics {
    std::vector<double> y_max;   ///< per DOF: max over one period of |y_i(t)| (fine grid,
                                 ///< polished by Newton on y_i' = 0: exact to rounding);
                                 ///< NaN for a DOF the Analyser was not asked to report
    std::vector<double> y_amp1;  ///< per DOF: first-harmonic amplitude sqrt(c1^2 + s1^2)
    std::vector<double> output_max;   ///< per Analyser output (model.hpp), in order: max over
                                      ///< one period of |o(t)| (polished as y_max)
    std::vector<double> output_amp1;  ///< per output: first-harmonic amplitude of o(t)
    double stick_fraction = 0;   ///< share of the AFT samples of contact 1 in stick phases, by
                                 ///< the law's own definition (stick_pattern below)
    std::string regime;          ///< "stick", "slip" or "stick-slip" (stick_pattern below) of
                                 ///< contact 1; "none" without contacts
    std::vector<ContactRegime> contacts;  ///< every contact's, in order (contacts[0]: the two above)
    double stick_indicator_max = 0;  ///< max over the samples of contact 1's stick indicator
                                     ///< (< 0: permanent stick)
    double stick_indicator_min = 0;  ///< min over the samples (>= 0: permanent slip)
    double energy = 0;           ///< friction energy dissipated per cycle, all contacts
    double input_energy = 0;     ///< work of the excitation per cycle, pi h sum_i F_i s_h,i (h: excitation harmonic)
    double viscous_energy = 0;   ///< energy dissipated per cycle by C: pi w sum_k k^2 (c_k' C c_k + s_k' C s_k)
    /// Energy balance of the harmonic-balance solution: |input - viscous - friction| per cycle,
    /// relative to max(pi h |F| |(c_h, s_h)|, input, viscous + |friction|), the first being the
    /// work the force could do on the response's harmonic h (0 when nothing moves). At a converged HB
    /// point it is at the level of the residual tolerance; above energy_balance_tolerance the
    /// point is suspect (flagged by hbf frf).
    double energy_error = 0;
};
/// Largest energy_error of an accepted point (PointMetrics) for a corrector tolerance:
/// max(1e-6, 100 tolerance). Measured at the default 1e-9: 1e-10..1e-9 on the paper's absorber
/// (every law) and the chain examples.
double energy_balance_limit(double tolerance);
// energy_imbalance (shared with time integration): model.hpp.
/// The displacement below which a response of `system` at `omega` is rounding, not motion:
/// 1e-9 |F|_inf / max(max|K_ii|, omega^2 max M_ii) (1e-9 of the quasi-static or mass-line
/// response). Floors the energy balance's reach (pi h |F| response_floor: a response held at
/// exactly zero by a stuck contact has no meaningful relative imbalance) and the peaks (a
/// maximum below |c|_1 response_floor is noise, not a peak).
double response_floor(const System& system, double omega);
/// Stick fraction and regime of a contact from its stick indicator samples phi (friction.hpp:
/// a sample sticks iff phi < 0). A stick phase is a run of cyclically consecutive sticking
/// samples at least `min_run` long. H harmonics cannot resolve shorter phases: at an
/// instantaneous stop (a velocity reversal in continuous slip) the dynamic Lagrangian's force
/// passes from -F_c to F_c within about one resolution cell 2 pi / (2H + 1), and those
/// samples stick; measured, such runs last 0.8-1.7 cells. So HB uses min_run = two cells,
/// ceil(2 N_t / (2H + 1)) samples (stick_phase_samples): shorter runs count as slip. regime:
/// "stick" (every sample sticks), "slip" (no stick phase) or "stick-slip"; fraction: share
/// of the samples in stick phases.
ContactRegime stick_pattern(const Eigen::VectorXd& phi, int min_run);
/// Shortest stick phase, in samples, that H harmonics on N_t samples resolve (see above).
int stick_phase_samples(int harmonics, int time_samples);

/// Samples per period of the fine reconstruction used for y_max and the stick fraction.
int fine_time_samples(int harmonics);

/// Computes PointMetrics; holds the fine-grid transform (planned once) for many points.
class Analyser {
public:
    /// `report`: the DOFs (0-based) whose y_max is computed (empty: all DOFs). y_amp1 and the
    /// input work are computed for every DOF (cheap).
    explicit Analyser(HarmonicBalance& hb, std::vector<int> report = {});
    /// y_max of the DOFs `report` only (none when empty), and output_max, output_amp1 of every
    /// output (validated against the system: InvalidInput).
    Analyser(HarmonicBalance& hb, std::vector<int> report, std::vector<Output> outputs);
    PointMetrics operator()(const SolutionPoint& point);

private:
    HarmonicBalance& hb_;
    Fourier fine_;
    std::vector<int> report_;
    std::vector<Output> outputs_;
};

/// The time signals of one solution over one period, on the AFT grid theta_j = 2 pi j / N_t
/// (t = theta / omega): every DOF, and contact `contact`'s relative displacement q, relative
/// velocity v = dq/dt, friction force f and stick indicator phi (friction.hpp: sticks iff
/// phi < 0). f against v is the friction loop (paper Figs. 5-6).
struct PointSignals {
    Eigen::VectorXd time;       ///< t_j = theta_j / omega
    Eigen::MatrixXd y;          ///< N_t x N: y_i(t_j)
    Eigen::VectorXd q, v, f, phi;  ///< f: the law's own force (FrictionModel::force_samples)
    Eigen::VectorXd f_series;      ///< f's H-harmonic Fourier series (what the balance sees)
    /// Every direction of the contact (System::contact_directions; q, f are the first column):
    /// N_t x s relative displacements and forces (laws elastic, unilateral: the tangential
    /// ones, then the normal displacement v and force N).
    Eigen::MatrixXd q_directions, f_directions;
};
/// A contact with several directions (friction.hpp: signals): q, v and f along its first
/// (tangential) direction, and every direction in q_directions, f_directions.
PointSignals point_signals(HarmonicBalance& hb, const SolutionPoint& point, int contact);

/// A resonance peak: a local maximum of max_t |y_dof(t)| (or of an output's |o(t)|) along a
/// branch.
struct Peak {
    double omega = 0;
    double y_max = 0;        ///< max over one period of |y_dof(t)| (|o(t)|) at the peak
    int branch = 1;
    bool refined = false;    ///< located by the search below (false: the best branch point)
    int output = 0;          ///< which of the outputs asked for (0-based; 0 for a single DOF)
    std::string why;         ///< refined = false: why not (refine_peak)
};

/// Whether a local maximum y of an output is a peak, not rounding: above `floor` (its weight
/// |c|_1 times response_floor) and above 1e-8 of the output's largest value on the branch (a
/// response held at zero by a stuck contact wiggles at the solver's tolerance).
bool is_peak_value(double y, double largest, double floor);
/// Refines `peak`, found at branch point m between its neighbours a and b (same branch, y(m)
/// = peak.y_max above both), by Brent's search in omega over the neighbours' interval with
/// value(omega, ok) (ok = false where the solve fails), until its bracket is below 1e-9 omega
/// (values locate a maximum in omega only to about sqrt(dy / c) relative, dy the values'
/// rounding relative to y and c = y'' omega^2 / (2 y) the peak's curvature: 1e-8 to 1e-7 on
/// sharp exact resonances; y_max itself is flat there, exact to its rounding). Not
/// refined, with the reason in peak.why: a fold among a, m, b, or omega not monotone through
/// them (y is not a function of omega there); a failed solve (its omega named); no value
/// above y(m) found (a corner of the curve, such as a stick/slip switch between two points).
/// A peak at a located transition (m of kind transition: a corner, located to 1e-10) is that
/// point, refined.
void refine_peak(Peak& peak, const SolutionPoint& a, const SolutionPoint& m, const SolutionPoint& b,
                 const std::function<double(double, bool&)>& value);
/// "N peak(s) not refined: <output> at w = W (why); ..." for the unrefined peaks (their
/// outputs' names in `names`, by Peak::output), or "" when every peak is refined.
std::string unrefined_peaks(const std::vector<Peak>& peaks, const std::vector<std::string>& names);

/// Peaks of DOF `dof` (0-based): every branch point whose y_max exceeds both neighbours on
/// the same branch, refined by a search in omega (Brent: parabolic steps, golden-section fallback) over the neighbours'
/// interval, solving exactly at each trial frequency (from the branch interpolation), to
/// |delta omega| <= 1e-9 omega (refine_peak; where it cannot, the branch point itself, with
/// refined = false and why).
std::vector<Peak> find_peaks(HarmonicBalance& hb, const BranchResult& branch, int dof, const CorrectorOptions& options);
/// The same for each output in turn (model.hpp): the peaks of outputs[0], then of outputs[1],
/// ..., each marked with its index in Peak::output.
std::vector<Peak> find_peaks(HarmonicBalance& hb, const BranchResult& branch, const std::vector<Output>& outputs,
                             const CorrectorOptions& options);

}  // namespace hbf
