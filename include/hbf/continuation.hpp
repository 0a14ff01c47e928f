// hbfriction — pseudo-arclength continuation in omega: its options, the branch data and how a
// continuation ends, the located folds and transitions, and samples of a branch.
//
// The continuation follows u = (X, omega) along R(X, omega) = 0. Distances along the branch are
// measured in scaled, dimensionless coordinates (X / x_ref, omega / omega_ref): x_ref = the
// largest unknown at the current point (HarmonicBalance::unknown_scale: at least a small
// displacement of the structure under the force), omega_ref = omega_end (omega_scale), so that
// a problem written in other units gives the same branch. The predictor steps by h along the
// unit tangent t (null vector of [dR/dX x_ref, dR/domega omega_ref], oriented like the
// previous one); the corrector (corrector.hpp) brings the prediction back onto R = 0 on the
// hyperplane through it normal to t.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hbf/corrector.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/linear_limits.hpp"

namespace hbf {

struct ContinuationOptions {
    double omega_start = 0.5;     ///< first frequency (the branch starts here)
    /// Last frequency (the branch stops here), >= omega_start; equal to it: one point, solved
    /// from a cold start by the start-point search (the linear guesses, from H = 12 on the
    /// solution with half the harmonics, then a ramp of the force), no continuation.
    double omega_end = 1.6;
    /// The harmonics of a first solve at each branch start (a cold start: omega_start, and
    /// omega_end or the middle of a gap after an amplitude cap): the start is searched with
    /// this many harmonics (the search below, automatic at its own H), and that solution,
    /// padded with zero harmonics, is Newton's start at the branch's H; where it does not
    /// converge there the search below runs at H (BranchResult::message says so). 0:
    /// automatic (from H = 12 on, half the harmonics after the linear guesses). Allowed 0 or
    /// the excitation's harmonic .. H - 1 (continue_branch checks it against H); at most
    /// max_harmonics.
    int start_harmonics = 0;
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
    /// (all branches): a progress display. May be empty. An exception it throws (other than
    /// InvalidInput) ends the branch like a solver failure: status solver_error, points kept.
    std::function<void(double omega, int points)> progress;
    /// Called before each marked fold is located (with locate_folds) with the folds done and
    /// their number: locating them can take longer than the branch (a 99-node interface's many
    /// folds at corners). May be empty; it must not throw.
    std::function<void(int done, int total)> fold_progress;
    /// Asked before each step, each restart, each solve of the search for a starting point (the
    /// force ramp of a cold start among them), each fold or transition to locate and, unless
    /// corrector.stop is set, each iteration of a correction (CorrectorOptions::stop): a non-empty
    /// answer (why: an interrupt, a time limit) stops the continuation with status stopped, the
    /// points computed so far kept (folds and transitions not yet located stay unmarked). May be
    /// empty; it must not throw.
    std::function<std::string()> stop;
};

/// cap: the last point of a trace stopped by the amplitude cap (an unbounded resonance; a
/// fold there stays a fold). branch_point, period_doubling, neimark_sacker: the first regular
/// point past a change of stability of that kind (stability.hpp: a real multiplier through +1
/// without a turn, through -1, a complex pair), set by the stability analysis.
enum class PointKind { regular, fold, sample, transition, cap, branch_point, period_doubling, neimark_sacker };
/// The regime boundary a transition point lies on (of the contact SolutionPoint::contact).
/// closed_lift_off: a contact with a normal direction closed all period on one side, opening
/// for part of it on the other (located by the exact polish only; the point is the grazing
/// orbit, on the closed side).
enum class Boundary { none, stick_stick_slip, stick_slip_slip, closed_lift_off };
/// "", "stick|stick-slip", "stick-slip|slip", "closed|lift-off".
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

/// How a continuation ended. completed: the branch spans [wmin, wmax]; every other status is
/// an incomplete result: amplitude_cap (the response exceeds max_amplitude: an unbounded
/// resonance, capped), left_range (the branch turned back out of the range before spanning
/// it), point_budget (max_points reached), stopped (ContinuationOptions::stop asked it: an
/// interrupt or a time limit), min_step (the corrector stalled), solver_error (the solver threw
/// during a step: a contact model that cannot evaluate the point, a broken-down linear solve;
/// the message says where and why, the points before it are kept), start_failed.
/// With several branches (restarts past a cap) the status is the worst of them, in the order
/// completed < amplitude_cap < left_range < point_budget < stopped < min_step < solver_error <
/// start_failed.
/// Throws InvalidInput naming the first option out of range (continue_branch calls it).
void validate(const ContinuationOptions& options);
/// The range of ContinuationOptions::start_harmonics against a balance of `harmonics` harmonics
/// whose force is at harmonic `load_harmonic`: 0, or load_harmonic..harmonics - 1 (harmonics
/// 0, not yet chosen: 0..max_harmonics). Throws InvalidInput naming start_harmonics.
void check_start_harmonics(int start_harmonics, int harmonics, int load_harmonic = 1);

enum class ContinuationStatus {
    completed,
    amplitude_cap,
    left_range,
    point_budget,
    stopped,
    min_step,
    solver_error,
    start_failed
};
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
    /// arclength corrector failed at the minimum step (continuation.cpp)
    int crossed_corners = 0;
    int unlocated_transitions = 0;      ///< regime changes between two points whose boundary
                                        ///< could not be located (named in message)
    /// fold or transition locations the solver ended by throwing (not located; the first
    /// exception's message in message)
    int location_errors = 0;
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

}  // namespace hbf
