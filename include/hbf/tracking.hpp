// hbfriction — following what a designer cares about through a second parameter p (the friction
// coefficient, the force, the tuning, a contact's key): the resonance peaks of an output and the
// stick-slip boundaries of the contacts, as curves in the (p, w) plane.
//
// The features start from one FRF at p_start (compute_frf: its refined peaks, its transitions)
// and are followed in p by a predictor (the secant of the last two points) and a corrector that
// solves the feature's condition at fixed p with w as the unknown:
//   * peak: dY/dw = 0, Y(w) = max over one period of |o(t)| of the output along the response at
//     (w, p). Y is what a designer reads (the map's and the FRF's peaks are its maxima); the first
//     harmonic's amplitude would be smoother but is not the displacement (the exact Coulomb
//     orbit's y_max differs from it by up to a few per cent). The derivative is a central
//     difference of two solves at w -+ h (h = 1e-5 w exact, 1e-4 w by HB), the second
//     derivative from the same three; Newton on it converges in 2-4 steps to |dw| <= 1e-10 w
//     (the FD truncation ~ h^2 Y'''/Y'' and the rounding ~ eps Y / (h Y'') stay below it on
//     peaks with Y'' w^2 / Y >= 10). A peak that sits on a stick/slip corner of Y (the two
//     sides' regimes differ within h) is the corner, located by bisection to 1e-12 w.
//   * boundary: where contact c's regime changes between stick and stick-slip or between
//     stick-slip and slip (a stick phase appears or vanishes). With the exact solver (exact
//     Coulomb, Jenkins) by bisection on the exact regime to 1e-12 w, and from full stick by
//     bisection on the permanent-stick load (closed form, event_exact.hpp) crossing 1; by
//     harmonic balance on the AFT regimes (O(1/H) misplaced, as hbf frf's transitions).
//   * fold: a limit point of the harmonic-balance FRF (dR/dX singular), followed with the
//     extended system (R = 0, J v = 0, l.v = 1) by pseudo-arclength in (X, v, w, p): through a
//     cusp, where two folds merge (the curve's p turns back; located by the secant method on
//     the tangent's p-component), back to the start's other fold (fold_tracking.cpp). Dense:
//     small models.
// Each solve starts from the previous one's state (the exact orbit's state at t = 0, or the HB
// coefficients), so the work per point is a few solves, not an FRF.
//
// Events: two peak curves exchange (their values cross: the equal-peak designs, located by
// regula falsi in p to 1e-10 |p|); a peak vanishes (it merges with a valley: no maximum found
// near the prediction down to the smallest step; the curve ends there, status vanished).
// A curve ends with left_range when its w leaves [wmin, wmax], amplitude_cap when its value
// exceeds the continuation's max_amplitude. After the run the peaks of an FRF at the last p
// reached are compared with the curves: a peak there that no curve reaches was born inside the
// range (a warning: tracking cannot see it).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "hbf/frf.hpp"
#include "hbf/model.hpp"
#include "hbf/optimize.hpp"
#include "hbf/verdict.hpp"

namespace hbf {

enum class TrackFeature { peak, boundary, fold };
/// "peak", "boundary", "fold".
std::string to_string(TrackFeature feature);

struct TrackOptions {
    TrackFeature feature = TrackFeature::peak;
    /// The parameter's range: followed from p_start to p_end (either order; finite, distinct).
    double p_start = 0, p_end = 0;
    /// Follow the feature nearest to this frequency at p_start only (within 10 % of it: an
    /// InvalidInput naming the features found otherwise); NaN: every one in [wmin, wmax].
    double omega = std::numeric_limits<double>::quiet_NaN();
    /// Steps in p relative to |p_end - p_start|: the largest (1e-6..0.5) and the smallest below
    /// which a curve that cannot be continued ends (vanished or failed), 1e-12..max_step.
    double max_step = 0.05;
    double min_step = 1e-7;
    int max_points = 5000;  ///< accepted points over all curves, 10..1000000
    /// Values of p (inside the range) where every live curve gets a point (kind "at").
    std::vector<double> at;
    /// boundary: the contact (0-based) whose boundaries are followed; -1: every contact's.
    int contact = -1;
    /// Called after each accepted step with the p reached (a progress display); may be empty.
    std::function<void(double p)> progress;
    /// Asked before every step in p: a non-empty answer (why: an interrupt, a time limit) ends
    /// every live curve there with status stopped and the answer in its message (the points so
    /// far kept; the check FRF at p_end is not computed). The FRF at p_start stops by
    /// settings.continuation.stop. Empty: never.
    std::function<std::string()> stop;

    /// Throws InvalidInput naming the first option out of range.
    void validate() const;
};

enum class TrackStatus {
    completed,      ///< reached p_end
    vanished,       ///< a peak merged with a valley (no maximum near it any more)
    left_range,     ///< w left [wmin, wmax]
    amplitude_cap,  ///< the value exceeded max_amplitude (an unbounded resonance)
    point_budget,   ///< max_points reached
    failed,         ///< the solves failed down to the smallest step
    stopped         ///< TrackOptions::stop asked it to end
};
/// "completed", "vanished", "left_range", "amplitude_cap", "point_budget", "failed", "stopped".
std::string to_string(TrackStatus status);

struct TrackPoint {
    double p = 0;
    double omega = 0;
    /// peak: Y at the peak (max over one period of |o(t)| of the output); boundary: the
    /// output's Y on the boundary (its stick side).
    double value = 0;
    /// "start" (p_start), "step", "at" (an asked value of p), "exchange" (two peaks equal),
    /// "cusp" (folds: where two folds merge),
    /// "search" (found while locating where the curve ends: the other curves have no point at
    /// that p), "end" (the curve's last point: its status says why).
    std::string kind = "step";
    /// The regime of the tracked contact (boundary) or of contact 1 (peak) at the point:
    /// stick, stick-slip, slip; "none" without contacts.
    std::string regime;
    /// peak: Y'' w^2 / Y at the peak (< 0: a maximum; -> 0 where it vanishes); "corner": NaN.
    double curvature = std::numeric_limits<double>::quiet_NaN();
    bool corner = false;  ///< peak: on a stick/slip corner of Y (the transition itself)
    /// The solver's state there (the exact orbit's state at t = 0, or the HB coefficients): a
    /// start for a later solve nearby (optimize_by_tracking).
    Eigen::VectorXd state;
};

struct TrackCurve {
    int id = 1;                ///< 1-based
    std::string label;         ///< "peak of y1 near w = 0.86", "contact 1 stick|stick-slip near w = 0.91"
    int contact = 0;           ///< boundary: 0-based contact
    Boundary boundary = Boundary::none;
    std::vector<TrackPoint> points;  ///< in the order followed
    TrackStatus status = TrackStatus::completed;
    std::string message;       ///< why it ended (status other than completed)
};

struct TrackEvent {
    std::string kind;  ///< "exchange" (two peaks' values cross), "vanished", "born" (a peak of the last FRF no curve reaches), "cusp" (two folds merge)
    double p = 0, omega = 0, value = 0;
    int curve = 0, other = 0;  ///< 1-based curves (other: exchange only; omega is curve's)
    double other_omega = 0;
};

struct TrackResult {
    TrackFeature feature = TrackFeature::peak;
    bool exact = false;   ///< solved by the event-exact solver (else harmonic balance)
    int harmonics = 0;    ///< H of the FRF at p_start (and of the HB solves)
    std::vector<TrackCurve> curves;
    std::vector<TrackEvent> events;
    long long solves = 0;  ///< periodic solves (exact orbits or HB corrections) after the start FRF
    int frfs = 0;          ///< FRFs computed (the start's and the check at the end)
    double p_reached = 0;  ///< the last p every live curve reached
    double seconds = 0;
    Verdict verdict;
    /// The largest value among the curves at each accepted p of the run (peak), with the curve.
    struct Largest {
        double p = 0, omega = 0, value = 0;
        int curve = 0;
        std::string kind;
    };
    std::vector<Largest> largest;
    std::string status() const { return verdict.status(); }
    /// One line: the feature, curves, events, solves and the verdict.
    std::string summary() const;
};

/// Follows `options.feature` of system(p) (the first of settings.outputs for peaks) from
/// p_start to p_end, with settings' harmonic balance, continuation range [omega_start,
/// omega_end], corrector and exact choice (settings.exact: the exact solver, which the peaks
/// and boundaries then are). Throws InvalidInput for bad options, a system(p) that throws at
/// p_start or p_end, or no feature near options.omega. The verdict: a curve that failed is an
/// error; left_range, amplitude_cap, point_budget, a peak born inside the range and a start FRF
/// that is not complete are warnings (exit 3); vanished peaks and exchanges are notes.
TrackResult track(const std::function<System(double)>& system, const FrfSettings& settings, const TrackOptions& options);

/// The design parameter that minimises the largest peak, by tracking (hbf optimize --method
/// tracking). First the scan of optimize_parameter (options.scan_points FRFs log-spaced over
/// [lower, upper], on options.threads): it finds the valley and brackets it between the best
/// scan value's neighbours (a best value at an end is at_bound, none bounded unbounded, as
/// there). Then the peaks of the first output are followed from the best scan value to both
/// neighbours; the largest peak along them (+infinity beyond a curve's amplitude cap or
/// failure) is minimised: at an exchange of the two largest peaks (kind "equal peaks", located
/// to 1e-10 |p| by the tracking), at an interior minimum of one curve (kind "minimum": Brent's
/// search in p between the neighbouring points, each value the peak located at that p, to
/// 1e-2 options.tolerance |p|), or where the largest peak ends (kind "peak end", to the
/// tracking's smallest step). An FRF at the minimum found checks it: tracking only follows the
/// peaks of its start, so a larger peak born in between starts the tracks again from there (at
/// most 3 times), and an unbounded FRF there fails the search (use the golden-section search).
struct TrackOptimum {
    OptimizeStatus status = OptimizeStatus::failed;
    double parameter = std::numeric_limits<double>::quiet_NaN();
    double value = std::numeric_limits<double>::quiet_NaN();  ///< the largest peak there
    double omega = std::numeric_limits<double>::quiet_NaN();  ///< its frequency
    double other_omega = std::numeric_limits<double>::quiet_NaN();  ///< equal peaks: the other's
    std::string kind;          ///< "equal peaks", "minimum", "peak end", "bound"
    std::vector<TrackResult> tracks;  ///< toward lower, toward upper
    long long solves = 0;
    int frfs = 0;
    double seconds = 0;
    std::string message;
    /// The largest refined peak of an FRF at the optimum (the check against peaks that tracking
    /// cannot see: those born between the start and the optimum).
    double check_value = std::numeric_limits<double>::quiet_NaN();
    int restarts = 0;  ///< rounds started again from the optimum after the check found a larger peak
    std::vector<double> scan, scan_values;  ///< the scan's parameters and largest peaks (+inf: unbounded)
    std::vector<std::string> failed_curves;  ///< curves whose solves failed (beyond them: unknown)
    /// One line: status, parameter (named `name`), the largest peak, kind, cost.
    std::string summary(const std::string& name = "p") const;
    /// converged: completed; at_bound a warning; unbounded and failed errors; curves whose
    /// solves failed a note (the largest peak counts as unknown beyond them, and the FRF at the
    /// optimum confirmed it); the tracks' notes as notes.
    Verdict verdict(const std::string& name = "p") const;
};
TrackOptimum optimize_by_tracking(const std::function<System(double)>& system, const FrfSettings& settings,
                                  const OptimizeOptions& options);

}  // namespace hbf
